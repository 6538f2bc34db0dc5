// 2D polygons: the shape of water regions and of solid walls (a box is a 4-point polygon), as Solids.
#pragma once

#include <vector>

#include "sluice/core/vec.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

class Polygon final : public Solid<2> {
 public:
  std::vector<Vec2> points;  // vertices in order (either orientation), implicitly closed

  explicit Polygon(std::vector<Vec2> vertices) : points(std::move(vertices)) {}
  static Polygon box(Vec2 lower, Vec2 upper);

  [[nodiscard]] bool contains(const Vec2& p) const override;  // strictly inside (crossing rule)
  [[nodiscard]] double signed_distance(const Vec2& p) const override;
  // The outward normal is along the line from p to the closest point (p inside) or back (p outside).
  [[nodiscard]] SurfacePoint<2> closest_surface_point(const Vec2& p) const override;
  void for_each_face_point(const Vec2& p, const std::function<void(const Vec2&)>& f) const override;
  void for_each_face_outside(const Vec2& p, double reach,
                             const std::function<void(const Vec2&, const Vec2&)>& f) const override;
  [[nodiscard]] Vec2 lower() const override;  // bounding box
  [[nodiscard]] Vec2 upper() const override;
  // Four vertices at the corners of its bounding box.
  [[nodiscard]] bool is_box() const override;
  // Rows parallel to each edge, and arcs around each reflex corner (see polygon.cpp).
  void fill_surface_layers(double dx, int layers, const std::function<void(const Vec2&)>& add) const override;

  [[nodiscard]] double distance_to_boundary(Vec2 p) const;
  [[nodiscard]] Vec2 closest_boundary_point(Vec2 p) const;
  [[nodiscard]] double area() const;  // unsigned

 private:
  [[nodiscard]] double twice_signed_area() const;  // positive if the points run counter-clockwise
};

}  // namespace sluice
