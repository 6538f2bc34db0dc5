#include "sluice/case/release_gate.hpp"

#include <fmt/format.h>

#include "sluice/case/case_error.hpp"

namespace sluice {

Case with_release_gate(const Case& c) {
  if (!c.release_gate) return c;
  if (c.water.empty() || c.water.front().shape != Shape::box)
    throw CaseError(fmt::format("release.gate = true holds the first [[water]] region behind a gate at its face "
                                "towards +x; expected a first [[water]] region with shape = \"box\", found {}",
                                c.water.empty() ? std::string("no [[water]]")
                                                : fmt::format("shape = \"{}\"", name_of(c.water.front().shape, shape_names))));
  for (const Region& w : c.walls)
    if (w.name == "gate")
      throw CaseError("release.gate = true adds a [[wall]] named \"gate\", and the case has one already; expected "
                      "another name for the case's wall");
  const int up = c.dimension - 1;
  const Region& water = c.water.front();
  const double top = water.max[up];
  Region gate;
  gate.name = "gate";
  gate.shape = Shape::box;
  gate.min = Vec3{};
  gate.max = c.tank_size();
  gate.min[0] = water.max[0];
  gate.max[0] = water.max[0] + 4.0 * c.dx;
  gate.max[up] = top + 4.0 * c.dx;
  gate.translation.law = MotionLawType::linear;
  gate.translation.direction = Vec3{};
  gate.translation.direction[up] = 1.0;
  gate.translation.speed = c.gate_speed;
  gate.translation.start = 0.0;
  gate.translation.end = (top + c.dx) / c.gate_speed;  // its foot dx above the water's top
  Case expanded = c;
  expanded.walls.push_back(gate);
  expanded.release_gate = false;
  return expanded;
}

}  // namespace sluice
