#include "sluice/geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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
  return Polygon{{lower, {upper[0], lower[1]}, upper, {lower[0], upper[1]}}};
}

bool Polygon::contains(Vec2 p) const {
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

double Polygon::distance_to_boundary(Vec2 p) const { return norm(closest_boundary_point(p) - p); }

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

double Polygon::area() const {
  double twice = 0.0;
  const std::size_t n = points.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++)
    twice += points[j][0] * points[i][1] - points[i][0] * points[j][1];
  return 0.5 * std::abs(twice);
}

}  // namespace sluice
