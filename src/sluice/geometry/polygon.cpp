#include "sluice/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <tuple>

namespace sluice {

namespace {

Vec2 closest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

}  // namespace

Polygon Polygon::box(Vec2 lower, Vec2 upper) {
  return Polygon({lower, {upper[0], lower[1]}, upper, {lower[0], upper[1]}});
}

bool Polygon::is_box() const {
  if (points.size() != 4) return false;
  const Vec2 lo = lower(), hi = upper();
  bool corner[2][2] = {{false, false}, {false, false}};
  for (const Vec2& q : points) {
    const bool x_lo = q[0] == lo[0], x_hi = q[0] == hi[0], y_lo = q[1] == lo[1], y_hi = q[1] == hi[1];
    if (!((x_lo || x_hi) && (y_lo || y_hi))) return false;
    corner[x_hi ? 1 : 0][y_hi ? 1 : 0] = true;
  }
  return corner[0][0] && corner[0][1] && corner[1][0] && corner[1][1];
}

bool Polygon::contains(const Vec2& p) const {
  bool inside = false;
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = points[i];
    const Vec2& b = points[j];
    if ((a[1] > p[1]) != (b[1] > p[1])) {
      const double x_cross = a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
      if (p[0] < x_cross) inside = !inside;
    }
  }
  return inside;
}

Vec2 Polygon::closest_boundary_point(Vec2 p) const {
  Vec2 best = points.front();
  double best_d2 = std::numeric_limits<double>::infinity();
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 c = closest_on_segment(p, points[j], points[i]);
    const Vec2 diff = c - p;
    const double d2 = dot(diff, diff);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = c;
    }
  }
  return best;
}

void Polygon::for_each_face_point(const Vec2& p, const std::function<void(const Vec2&)>& f) const {
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) f(closest_on_segment(p, points[j], points[i]));
}

void Polygon::for_each_face_outside(const Vec2& p, double reach,
                                    const std::function<void(const Vec2&, const Vec2&)>& f) const {
  const double orientation = twice_signed_area() > 0.0 ? 1.0 : -1.0;  // +1: counter-clockwise
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = points[j], ab = points[i] - points[j];
    const double length = norm(ab);
    if (!(length > 0.0)) continue;
    const Vec2 tangent = (1.0 / length) * ab;
    const Vec2 outward = orientation * Vec2{tangent[1], -tangent[0]};
    const double along = dot(p - a, tangent), off = dot(p - a, outward);
    if (along > 0.0 && along < length && off > 0.0 && off < reach) f(a + along * tangent, outward);
  }
}

double Polygon::distance_to_boundary(Vec2 p) const { return norm(closest_boundary_point(p) - p); }

double Polygon::signed_distance(const Vec2& p) const {
  const double d = distance_to_boundary(p);
  return contains(p) ? -d : d;
}

SurfacePoint<2> Polygon::closest_surface_point(const Vec2& p) const {
  SurfacePoint<2> s{closest_boundary_point(p), {}};
  const Vec2 towards = s.point - p;
  const double len = norm(towards);
  if (len > 0.0) s.normal = (contains(p) ? 1.0 : -1.0) / len * towards;
  return s;
}

// Rows parallel to each edge at depths (k + 1/2) dx, spaced about dx along the edge, and arcs of the
// same depths around each reflex corner (where the solid wraps around the water and the rows of the two
// edges leave a wedge empty). Only points inside the polygon are kept.
void Polygon::fill_surface_layers(double dx, int layers, const std::function<void(const Vec2&)>& add) const {
  const std::size_t n = points.size();
  const double orientation = twice_signed_area() > 0.0 ? 1.0 : -1.0;  // +1: counter-clockwise
  auto edge = [&](std::size_t k) {
    const Vec2 a = points[k], b = points[(k + 1) % n];
    const double length = norm(b - a);
    const Vec2 tangent = (1.0 / length) * (b - a);
    const Vec2 inward = orientation * Vec2{-tangent[1], tangent[0]};  // into the solid
    return std::tuple{a, length, tangent, inward};
  };
  auto keep = [&](Vec2 p) {
    if (contains(p)) add(p);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const auto [a, length, tangent, inward] = edge(k);
    if (length <= 0.0) continue;
    const int along = std::max(1, static_cast<int>(std::lround(length / dx)));
    const double spacing = length / along;
    for (int layer = 0; layer < layers; ++layer) {
      const double depth = (layer + 0.5) * dx;
      for (int j = 0; j < along; ++j) keep(a + ((j + 0.5) * spacing) * tangent + depth * inward);
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    const auto [a_in, len_in, t_in, n_in] = edge((k + n - 1) % n);
    const auto [vertex, len_out, t_out, n_out] = edge(k);
    const double turn = orientation * (t_in[0] * t_out[1] - t_in[1] * t_out[0]);
    if (turn >= -1e-12) continue;  // convex (or straight) corner of the solid: the rows overlap
    const double start = std::atan2(n_in[1], n_in[0]);
    double sweep = std::atan2(n_out[1], n_out[0]) - start;
    while (sweep <= -std::numbers::pi) sweep += 2.0 * std::numbers::pi;
    while (sweep > std::numbers::pi) sweep -= 2.0 * std::numbers::pi;
    for (int layer = 0; layer < layers; ++layer) {
      const double radius = (layer + 0.5) * dx;
      const int count = static_cast<int>(std::lround(radius * std::abs(sweep) / dx));
      for (int j = 0; j < count; ++j) {
        const double angle = start + (j + 0.5) * sweep / count;
        keep(vertex + radius * Vec2{std::cos(angle), std::sin(angle)});
      }
    }
  }
}

Vec2 Polygon::lower() const {
  Vec2 lo = points.front();
  for (const Vec2& q : points) lo = {std::min(lo[0], q[0]), std::min(lo[1], q[1])};
  return lo;
}

Vec2 Polygon::upper() const {
  Vec2 hi = points.front();
  for (const Vec2& q : points) hi = {std::max(hi[0], q[0]), std::max(hi[1], q[1])};
  return hi;
}

double Polygon::twice_signed_area() const {
  double twice = 0.0;
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
    twice += points[j][0] * points[i][1] - points[i][0] * points[j][1];
  return twice;
}

double Polygon::area() const { return 0.5 * std::abs(twice_signed_area()); }

}  // namespace sluice
