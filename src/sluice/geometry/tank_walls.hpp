// The tank's own walls as one Solid, for a tank that moves: everything outside its inside, the box
// [0, size] (open at the top when the tank has no lid). The water is inside; a point of the walls is
// one outside. Its surface is the inside's faces, and its bounds those of the wall particles' layers
// (`depth` thick) around them.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "sluice/geometry/box.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

template <int Dim>
class TankWalls final : public Solid<Dim> {
 public:
  // The inside [0, size]; without a lid it is open upwards. The bounds: the walls' layers, `depth`
  // thick, up to the side walls' top (and over the lid).
  TankWalls(const Vec<Dim>& size, bool lid, double depth) : upper_inside_(size) {
    constexpr int up = Dim - 1;
    for (int d = 0; d < Dim; ++d) {
      lower_[d] = -depth;
      upper_[d] = size[d] + depth;
    }
    if (!lid) {
      upper_inside_[up] = std::numeric_limits<double>::infinity();
      upper_[up] = size[up];
    }
  }

  [[nodiscard]] bool contains(const Vec<Dim>& x) const override { return !inside(x); }

  // Inside the tank: the distance to its nearest face; in the walls: minus the distance to the inside.
  [[nodiscard]] double signed_distance(const Vec<Dim>& x) const override {
    if (inside(x)) return face_distance(x).first;
    return -norm(clamped(x) - x);
  }

  [[nodiscard]] SurfacePoint<Dim> closest_surface_point(const Vec<Dim>& x) const override {
    SurfacePoint<Dim> s;
    if (inside(x)) {
      const auto [distance, face] = face_distance(x);
      const int d = face / 2;
      s.point = x;
      s.point[d] = face % 2 == 0 ? 0.0 : upper_inside_[d];
      s.normal[d] = face % 2 == 0 ? 1.0 : -1.0;  // out of the walls, into the tank
      (void)distance;
      return s;
    }
    s.point = clamped(x);
    const Vec<Dim> towards = s.point - x;
    const double len = norm(towards);
    if (len > 0.0) s.normal = (1.0 / len) * towards;
    return s;
  }

  [[nodiscard]] Vec<Dim> lower() const override { return lower_; }
  [[nodiscard]] Vec<Dim> upper() const override { return upper_; }

  void for_each_face_point(const Vec<Dim>& x, const std::function<void(const Vec<Dim>&)>& f) const override {
    for_each_box_face_point<Dim>(Vec<Dim>{}, upper_inside_, x, f);
  }

  // Every face within `reach` of a point inside the tank: in its corners, two (three in 3D).
  void for_each_face_outside(const Vec<Dim>& x, double reach,
                             const std::function<void(const Vec<Dim>&, const Vec<Dim>&)>& f) const override {
    if (!inside(x)) return;
    for (int d = 0; d < Dim; ++d)
      for (int side = 0; side < 2; ++side) {
        const double face = side == 0 ? 0.0 : upper_inside_[d];
        if (!std::isfinite(face) || !(std::abs(x[d] - face) < reach)) continue;
        Vec<Dim> foot = x, normal{};
        foot[d] = face;
        normal[d] = side == 0 ? 1.0 : -1.0;
        f(foot, normal);
      }
  }

  // The tank's particles are placed by the set-up's slabs, not by this solid.
  void fill_surface_layers(double, int, const std::function<void(const Vec<Dim>&)>&) const override {}

 private:
  [[nodiscard]] bool inside(const Vec<Dim>& x) const {
    for (int d = 0; d < Dim; ++d)
      if (!(x[d] > 0.0 && x[d] < upper_inside_[d])) return false;
    return true;
  }
  [[nodiscard]] Vec<Dim> clamped(const Vec<Dim>& x) const {
    Vec<Dim> q{};
    for (int d = 0; d < Dim; ++d) q[d] = std::clamp(x[d], 0.0, upper_inside_[d]);
    return q;
  }
  // The distance from a point inside to its nearest face, and which (2 d + 0 low, 2 d + 1 high).
  [[nodiscard]] std::pair<double, int> face_distance(const Vec<Dim>& x) const {
    double best = std::numeric_limits<double>::infinity();
    int face = 0;
    for (int d = 0; d < Dim; ++d) {
      if (x[d] < best) best = x[d], face = 2 * d;
      if (upper_inside_[d] - x[d] < best) best = upper_inside_[d] - x[d], face = 2 * d + 1;
    }
    return {best, face};
  }

  Vec<Dim> upper_inside_;
  Vec<Dim> lower_{}, upper_{};
};

}  // namespace sluice
