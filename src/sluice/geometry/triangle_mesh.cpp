#include "sluice/geometry/triangle_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace sluice {

namespace {

Vec<3> cross(const Vec<3>& a, const Vec<3>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

std::string point_text(const Vec<3>& p) { return fmt::format("({:g}, {:g}, {:g})", p[0], p[1], p[2]); }

}  // namespace

Vec<3> TriangleMesh::lower() const {
  Vec<3> lo{};
  lo.fill(std::numeric_limits<double>::infinity());
  for (const auto& v : vertices)
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], v[d]);
  return lo;
}

Vec<3> TriangleMesh::upper() const {
  Vec<3> hi{};
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const auto& v : vertices)
    for (int d = 0; d < 3; ++d) hi[d] = std::max(hi[d], v[d]);
  return hi;
}

double TriangleMesh::signed_volume() const {
  // The sum of the tetrahedra from a point to each triangle; the point is the first vertex, which keeps
  // the terms small for a mesh far from the origin.
  if (vertices.empty()) return 0.0;
  const Vec<3> o = vertices[0];
  double six_volume = 0.0;
  for (const auto& t : triangles)
    six_volume += dot(vertices[t[0]] - o, cross(vertices[t[1]] - o, vertices[t[2]] - o));
  return six_volume / 6.0;
}

void TriangleMesh::place(double scale, const Vec<3>& offset) {
  for (auto& v : vertices) v = scale * v + offset;
}

void check_closed_mesh(const TriangleMesh& m) {
  if (m.triangles.empty()) throw MeshError("it holds no triangles; expected a closed triangle surface");
  for (const auto& t : m.triangles)
    for (std::uint32_t i : t)
      if (i >= m.vertices.size())
        throw MeshError(fmt::format("a triangle refers to vertex {} of {}", i + 1, m.vertices.size()));
  // Each vertex, before the bounding box: std::min and std::max pass over a NaN.
  for (std::size_t k = 0; k < m.vertices.size(); ++k)
    if (!std::isfinite(m.vertices[k][0]) || !std::isfinite(m.vertices[k][1]) || !std::isfinite(m.vertices[k][2]))
      throw MeshError(fmt::format("vertex {} {} is not finite; expected three finite coordinates", k + 1,
                                  point_text(m.vertices[k])));
  const Vec<3> lo = m.lower(), hi = m.upper();
  const double size = norm(hi - lo);
  if (!std::isfinite(size))
    throw MeshError(fmt::format("it spans from {} to {}, beyond the range of numbers; expected a mesh of a finite size",
                                point_text(lo), point_text(hi)));
  // A triangle whose area is below this (relative to the mesh's size squared) has no direction.
  const double min_twice_area = 1e-12 * size * size;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const auto& t = m.triangles[k];
    const Vec<3> a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || norm(cross(b - a, c - a)) <= min_twice_area)
      throw MeshError(fmt::format("triangle {} with corners {}, {}, {} is degenerate (no area); expected triangles "
                                  "with three distinct corners not on one line",
                                  k + 1, point_text(a), point_text(b), point_text(c)));
  }
  // Each directed edge (from, to) once: the two triangles of an edge run along it in opposite
  // directions, so in a closed, consistently oriented surface each directed edge appears once and its
  // reverse once.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> directed;
  for (std::size_t k = 0; k < m.triangles.size(); ++k) {
    const auto& t = m.triangles[k];
    for (int e = 0; e < 3; ++e) {
      const std::pair<std::uint32_t, std::uint32_t> edge{t[e], t[(e + 1) % 3]};
      if (!directed.emplace(edge, k).second) {
        const std::pair<std::uint32_t, std::uint32_t> reverse{edge.second, edge.first};
        const bool more_than_two = directed.contains(reverse);
        throw MeshError(fmt::format(
            "the edge from {} to {} {}; expected a closed surface whose triangles are all ordered the same way "
            "round (each edge shared by exactly two triangles, which run along it in opposite directions)",
            point_text(m.vertices[edge.first]), point_text(m.vertices[edge.second]),
            more_than_two ? "belongs to more than two triangles"
                          : fmt::format("runs the same way in triangles {} and {} (their orders disagree)",
                                        directed.at(edge) + 1, k + 1)));
      }
    }
  }
  for (const auto& [edge, k] : directed)
    if (!directed.contains({edge.second, edge.first}))
      throw MeshError(fmt::format("it is not closed: the edge from {} to {} belongs to triangle {} only; expected a "
                                  "closed surface (each edge shared by exactly two triangles)",
                                  point_text(m.vertices[edge.first]), point_text(m.vertices[edge.second]), k + 1));
  // Around each vertex its triangles form one fan: following them from one to the next (the triangle
  // (v, a, b) leads to the one that starts with (v, b)) visits them all. Two surfaces touching at a
  // corner do not.
  std::map<std::uint32_t, std::map<std::uint32_t, std::uint32_t>> fans;  // v -> (a -> b)
  for (const auto& t : m.triangles)
    for (int e = 0; e < 3; ++e) fans[t[e]][t[(e + 1) % 3]] = t[(e + 2) % 3];
  for (const auto& [v, fan] : fans) {
    std::size_t steps = 0;
    std::uint32_t at = fan.begin()->first;
    do {
      at = fan.at(at);
      ++steps;
    } while (at != fan.begin()->first && steps <= fan.size());
    if (steps != fan.size())
      throw MeshError(fmt::format("the surface touches itself at the corner {} (its triangles there form more than "
                                  "one fan); expected a closed surface that does not touch itself",
                                  point_text(m.vertices[v])));
  }
  const double volume = m.signed_volume();
  if (!(volume > 1e-12 * size * size * size)) {
    if (volume < 0.0)
      throw MeshError(fmt::format("it is inside out: its signed volume is {:g} (its normals point inwards); expected "
                                  "a positive volume, with the triangles' corners counter-clockwise seen from outside",
                                  volume));
    throw MeshError(fmt::format("it encloses no volume (signed volume {:g}); expected a closed solid", volume));
  }
}

}  // namespace sluice
