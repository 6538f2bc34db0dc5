// Small queries of the wall solids near a particle, shared by leak handling (geometry/leaks.cpp) and
// the wall friction (physics/wall_friction.cpp): each solid with a grown bounding box for a quick
// reject, and the outward normal of the surface nearest a point.
#pragma once

#include <cmath>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice::near_solids {

template <int Dim>
struct Bounded {
  const Solid<Dim>* solid;
  Vec<Dim> lower, upper;                 // grown by the margin
  Vec<Dim> solid_lower, solid_upper;     // the solid's own bounds
  bool box;                              // Solid::is_box
  bool moving;                           // Solid::moves
};

// Each solid with its bounding box grown by `margin` on every side.
template <int Dim>
std::vector<Bounded<Dim>> bounded(const Solids<Dim>& solids, double margin) {
  std::vector<Bounded<Dim>> boxes;
  boxes.reserve(solids.size());
  for (const auto& s : solids) {
    Vec<Dim> lower = s->lower(), upper = s->upper();
    for (int d = 0; d < Dim; ++d) {
      lower[d] -= margin;
      upper[d] += margin;
    }
    boxes.push_back({s.get(), lower, upper, s->lower(), s->upper(), s->is_box(), s->moves()});
  }
  return boxes;
}

template <int Dim>
bool in_box(const Bounded<Dim>& b, const Vec<Dim>& x) {
  for (int d = 0; d < Dim; ++d)
    if (!(x[d] > b.lower[d] && x[d] < b.upper[d])) return false;
  return true;
}

template <int Dim>
const Solid<Dim>* containing(const std::vector<Bounded<Dim>>& solids, const Vec<Dim>& x) {
  for (const Bounded<Dim>& b : solids)
    if (in_box<Dim>(b, x) && b.solid->contains(x)) return b.solid;
  return nullptr;
}

// The solid's outward surface normal nearest x, at signed distance `distance`. On the surface itself
// the direction to the closest point is undefined: there the gradient of the signed distance, by
// central differences.
template <int Dim>
Vec<Dim> outward_normal(const Solid<Dim>& solid, const Vec<Dim>& x, double distance, double dx) {
  if (std::abs(distance) > 1e-6 * dx) return solid.closest_surface_point(x).normal;
  const double step = 1e-4 * dx;
  Vec<Dim> gradient{};
  for (int d = 0; d < Dim; ++d) {
    Vec<Dim> plus = x, minus = x;
    plus[d] += step;
    minus[d] -= step;
    gradient[d] = solid.signed_distance(plus) - solid.signed_distance(minus);
  }
  const double length = norm(gradient);
  return length > 0.0 ? (1.0 / length) * gradient : Vec<Dim>{};
}

template <int Dim>
Vec<Dim> position_of(const Particles<Dim>& p, long i) {
  Vec<Dim> x{};
  for (int d = 0; d < Dim; ++d) x[d] = p.position[d][i];
  return x;
}


}  // namespace sluice::near_solids
