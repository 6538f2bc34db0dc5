// 2D polygons: the shape of water regions and of solid walls (a box is a 4-point polygon).
#pragma once

#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

struct Polygon {
  std::vector<Vec2> points;  // vertices in order (either orientation), implicitly closed

  static Polygon box(Vec2 lower, Vec2 upper);

  [[nodiscard]] bool contains(Vec2 p) const;                 // strictly inside (crossing rule)
  [[nodiscard]] double distance_to_boundary(Vec2 p) const;
  [[nodiscard]] Vec2 closest_boundary_point(Vec2 p) const;
  [[nodiscard]] Vec2 lower() const;                          // bounding box
  [[nodiscard]] Vec2 upper() const;
  [[nodiscard]] double area() const;                         // unsigned
};

}  // namespace sluice
