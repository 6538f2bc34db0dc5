// An axis-aligned box as a Solid, in any dimension.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "sluice/geometry/lattice.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

// The point of each face of the box [lower, upper] nearest to x (x clamped into the face); a face at
// an infinite bound is skipped.
template <int Dim, class F>
void for_each_box_face_point(const Vec<Dim>& lower, const Vec<Dim>& upper, const Vec<Dim>& x, F&& f) {
  Vec<Dim> clamped{};
  for (int d = 0; d < Dim; ++d) clamped[d] = std::clamp(x[d], lower[d], upper[d]);
  for (int d = 0; d < Dim; ++d)
    for (double face : {lower[d], upper[d]}) {
      if (!std::isfinite(face)) continue;
      Vec<Dim> q = clamped;
      q[d] = face;
      f(q);
    }
}

template <int Dim>
class Box final : public Solid<Dim> {
 public:
  Box(const Vec<Dim>& lower, const Vec<Dim>& upper) : lower_(lower), upper_(upper) {}

  [[nodiscard]] bool contains(const Vec<Dim>& x) const override {
    for (int d = 0; d < Dim; ++d)
      if (!(x[d] > lower_[d] && x[d] < upper_[d])) return false;
    return true;
  }

  [[nodiscard]] bool is_box() const override { return true; }

  [[nodiscard]] double signed_distance(const Vec<Dim>& x) const override {
    // Outside: the distance to the box; inside: minus the distance to the nearest face.
    double outside2 = 0.0, inside = -std::numeric_limits<double>::infinity();
    for (int d = 0; d < Dim; ++d) {
      const double below = lower_[d] - x[d], above = x[d] - upper_[d];
      const double gap = std::max(below, above);
      if (gap > 0.0) outside2 += gap * gap;
      inside = std::max(inside, gap);
    }
    return outside2 > 0.0 ? std::sqrt(outside2) : inside;
  }

  [[nodiscard]] SurfacePoint<Dim> closest_surface_point(const Vec<Dim>& x) const override {
    SurfacePoint<Dim> s;
    if (!contains(x)) {
      for (int d = 0; d < Dim; ++d) s.point[d] = std::clamp(x[d], lower_[d], upper_[d]);
      Vec<Dim> out = x - s.point;
      const double len = norm(out);
      if (len > 0.0) {
        s.normal = (1.0 / len) * out;
        return s;
      }
    }
    // Inside (or on the surface): the nearest face.
    int axis = 0;
    bool high = false;
    double best = std::numeric_limits<double>::infinity();
    for (int d = 0; d < Dim; ++d) {
      if (x[d] - lower_[d] < best) best = x[d] - lower_[d], axis = d, high = false;
      if (upper_[d] - x[d] < best) best = upper_[d] - x[d], axis = d, high = true;
    }
    s.point = x;
    s.point[axis] = high ? upper_[axis] : lower_[axis];
    s.normal = Vec<Dim>{};
    s.normal[axis] = high ? 1.0 : -1.0;
    return s;
  }

  void for_each_face_point(const Vec<Dim>& x, const std::function<void(const Vec<Dim>&)>& f) const override {
    for_each_box_face_point<Dim>(lower_, upper_, x, f);
  }

  [[nodiscard]] Vec<Dim> lower() const override { return lower_; }
  [[nodiscard]] Vec<Dim> upper() const override { return upper_; }

  // A lattice anchored at the lower corner, keeping the points within layers x dx of a face.
  void fill_surface_layers(double dx, int layers, const std::function<void(const Vec<Dim>&)>& add) const override {
    const double depth = layers * dx;
    for_each_lattice_point<Dim>(lower_, lower_, upper_, dx, [&](const Vec<Dim>& x) {
      if (-signed_distance(x) < depth) add(x);
    });
  }

 private:
  Vec<Dim> lower_, upper_;
};

}  // namespace sluice
