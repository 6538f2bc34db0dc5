// The one interface of every shape that bounds water or walls: an inside test, the signed distance
// and the closest surface point with its outward normal (leak detection and put-back, water placement),
// and filling with wall particles. Behind it: polygons in 2D (geometry/polygon.hpp) and boxes in 2D
// and 3D (geometry/box.hpp).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

template <int Dim>
struct SurfacePoint {
  Vec<Dim> point{};
  Vec<Dim> normal{};  // unit, pointing out of the solid
};

template <int Dim>
class Solid {
 public:
  virtual ~Solid() = default;

  // Strictly inside.
  [[nodiscard]] virtual bool contains(const Vec<Dim>& x) const = 0;
  // Distance to the surface, negative inside.
  [[nodiscard]] virtual double signed_distance(const Vec<Dim>& x) const = 0;
  [[nodiscard]] virtual SurfacePoint<Dim> closest_surface_point(const Vec<Dim>& x) const = 0;
  // Bounding box.
  [[nodiscard]] virtual Vec<Dim> lower() const = 0;
  [[nodiscard]] virtual Vec<Dim> upper() const = 0;
  // Whether the solid moves (MovingSolid), and the velocity of its material at x (zero at rest).
  [[nodiscard]] virtual bool moves() const { return false; }
  [[nodiscard]] virtual Vec<Dim> velocity_at(const Vec<Dim>& /*x*/) const { return {}; }
  // Whether the solid is its bounding box, an axis-aligned box: then the closest point to a point
  // outside it is that point clamped into [lower(), upper()].
  [[nodiscard]] virtual bool is_box() const { return false; }
  // Calls f(q) with the point q of each face (an edge in 2D) nearest to x: the candidates for the
  // nearest point of the surface that water touches, where a face may be covered by another solid.
  virtual void for_each_face_point(const Vec<Dim>& x, const std::function<void(const Vec<Dim>&)>& f) const = 0;
  // Calls f(foot, normal) for each face x lies outside of (on the side its outward `normal` points to)
  // within `reach`, whose foot of the perpendicular from x lies inside the face. Where two faces meet
  // at a corner that wraps around the water (a polygon's reflex vertex) a particle in the corner is
  // near both, and the nearest surface point names only one of them. Convex shapes and meshes call
  // nothing: for them the nearest surface point is enough.
  virtual void for_each_face_outside(const Vec<Dim>& /*x*/, double /*reach*/,
                                     const std::function<void(const Vec<Dim>&, const Vec<Dim>&)>& /*f*/) const {}
  // Calls add(x) for the wall particles of the solid: points inside it, in `layers` layers spaced dx
  // below its surface (the first at dx/2), about dx apart along it.
  virtual void fill_surface_layers(double dx, int layers, const std::function<void(const Vec<Dim>&)>& add) const = 0;
};

template <int Dim>
using Solids = std::vector<std::shared_ptr<const Solid<Dim>>>;

}  // namespace sluice
