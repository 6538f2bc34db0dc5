// Small cases for the physics tests, written as case files so they read like what a user writes.
#pragma once

#include <string>

#include "sluice/case/params.hpp"

namespace sluice::test_cases {

// Still water of depth `depth` in a tank `width` wide.
inline Case hydrostatic_tank(double width, double depth, double dx, const std::string& integrator, double cfl) {
  return parse_case(R"(
[case]
name = "hydrostatic"
[domain]
dx = )" + std::to_string(dx) + R"(
[tank]
width = )" + std::to_string(width) + R"(
height = )" + std::to_string(1.2 * depth) + R"(
[fluid]
sound_speed = 30.0
[time]
integrator = ")" + integrator + R"("
cfl = )" + std::to_string(cfl) + R"(
[[water]]
min = [0.0, 0.0]
max = [)" + std::to_string(width) + ", " + std::to_string(depth) + R"(]
)",
                    "hydrostatic test case");
}

}  // namespace sluice::test_cases
