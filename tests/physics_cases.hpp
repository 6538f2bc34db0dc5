// Small cases for the physics tests, written as case files so they read like what a user writes. They
// state their walls (dynamic, h = 1.3 dx, no shifting): the tests' bounds were measured with them, and
// a test that wants other walls says so with overrides.
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
h_over_dx = 1.3
[tank]
width = )" + std::to_string(width) + R"(
height = )" + std::to_string(1.2 * depth) + R"(
[fluid]
sound_speed = 30.0
[physics]
wall_boundary = "dynamic"
wall_friction = "none"
shifting = 0.0
[time]
integrator = ")" + integrator + R"("
cfl = )" + std::to_string(cfl) + R"(
[[water]]
min = [0.0, 0.0]
max = [)" + std::to_string(width) + ", " + std::to_string(depth) + R"(]
)",
                    "hydrostatic test case");
}

// A tank whose water goes over its far wall: gravity tilted 45 degrees towards that wall (the tank
// accelerating away from it at g) drives a column 0.1 m wide and 0.15 m high along the floor into the
// wall, and the water piles up there higher than the wall (0.15 m; a slope of 1 would stand 0.17 m
// at rest). With `lid`, the tank is closed at the wall's height.
inline Case spill_over_wall(double dx, bool lid, double end) {
  return parse_case(R"(
[case]
name = "spill"
[domain]
dx = )" + std::to_string(dx) + R"(
h_over_dx = 1.3
[tank]
width = 0.4
height = 0.15
lid = )" + (lid ? "true" : "false") + R"(
[physics]
gravity = [9.81, -9.81]
wall_boundary = "dynamic"
wall_friction = "none"
shifting = 0.0
[fluid]
sound_speed = 30.0
[time]
end = )" + std::to_string(end) + R"(
[[water]]
min = [0.0, 0.0]
max = [0.1, 0.15]
)",
                    "spill test case");
}

}  // namespace sluice::test_cases
