#include "sluice/geometry/mass_properties.hpp"

#include <cmath>
#include <stdexcept>

namespace sluice {

namespace {

// From the second moments about the origin, C = int r r^T dV (xx, yy, zz, xy, xz, yz), the volume
// and the centroid: the inertia about the centroid.
std::array<double, 6> inertia_about_centroid(std::array<double, 6> C, double volume, const Vec3& c) {
  C[0] -= volume * c[0] * c[0];
  C[1] -= volume * c[1] * c[1];
  C[2] -= volume * c[2] * c[2];
  C[3] -= volume * c[0] * c[1];
  C[4] -= volume * c[0] * c[2];
  C[5] -= volume * c[1] * c[2];
  const double trace = C[0] + C[1] + C[2];
  return {trace - C[0], trace - C[1], trace - C[2], -C[3], -C[4], -C[5]};
}

MassProperties box(const Region& r, int dimension) {
  MassProperties m;
  m.volume = 1.0;
  Vec3 size{};
  for (int d = 0; d < dimension; ++d) {
    size[d] = r.max[d] - r.min[d];
    m.volume *= size[d];
    m.centroid[d] = 0.5 * (r.min[d] + r.max[d]);
  }
  const double a2 = size[0] * size[0], b2 = size[1] * size[1], c2 = size[2] * size[2];
  m.inertia = {m.volume * (b2 + c2) / 12.0, m.volume * (a2 + c2) / 12.0, m.volume * (a2 + b2) / 12.0, 0.0, 0.0, 0.0};
  return m;
}

// Green's theorem over the edges (either orientation: the signed area's sign is divided out).
MassProperties polygon(const Region& r) {
  const auto& p = r.points;
  double area = 0.0, cx = 0.0, cy = 0.0, xx = 0.0, yy = 0.0, xy = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % p.size()];
    const double cross = a[0] * b[1] - b[0] * a[1];
    area += cross;
    cx += (a[0] + b[0]) * cross;
    cy += (a[1] + b[1]) * cross;
    xx += (a[0] * a[0] + a[0] * b[0] + b[0] * b[0]) * cross;
    yy += (a[1] * a[1] + a[1] * b[1] + b[1] * b[1]) * cross;
    xy += (a[0] * b[1] + 2.0 * a[0] * a[1] + 2.0 * b[0] * b[1] + b[0] * a[1]) * cross;
  }
  area *= 0.5;
  MassProperties m;
  m.volume = std::abs(area);
  m.centroid = {cx / (6.0 * area), cy / (6.0 * area), 0.0};
  const std::array<double, 6> C = {xx / (12.0 * area) * m.volume, yy / (12.0 * area) * m.volume, 0.0,
                                   xy / (24.0 * area) * m.volume, 0.0, 0.0};
  m.inertia = inertia_about_centroid(C, m.volume, m.centroid);
  return m;
}

// Signed tetrahedra from the origin to each triangle (outward, counter-clockwise seen from outside).
MassProperties mesh(const Region& r) {
  if (!r.mesh) throw std::invalid_argument("mass_properties: a mesh region without its mesh");
  double volume = 0.0;
  Vec3 moment{};
  std::array<double, 6> C{};
  for (const auto& t : r.mesh->triangles) {
    const Vec3 &a = r.mesh->vertices[t[0]], &b = r.mesh->vertices[t[1]], &c = r.mesh->vertices[t[2]];
    const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                       a[2] * (b[0] * c[1] - b[1] * c[0]);
    volume += det / 6.0;
    for (int d = 0; d < 3; ++d) moment[d] += det / 24.0 * (a[d] + b[d] + c[d]);
    // int x_i x_j over the tetrahedron (0, a, b, c) = det/120 (sum_k u_k,i u_k,j + (sum_k u_k,i)(sum_k u_k,j)).
    const auto second = [&](int i, int j) {
      return det / 120.0 *
             (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + (a[i] + b[i] + c[i]) * (a[j] + b[j] + c[j]));
    };
    C[0] += second(0, 0);
    C[1] += second(1, 1);
    C[2] += second(2, 2);
    C[3] += second(0, 1);
    C[4] += second(0, 2);
    C[5] += second(1, 2);
  }
  MassProperties m;
  m.volume = volume;
  for (int d = 0; d < 3; ++d) m.centroid[d] = moment[d] / volume;
  m.inertia = inertia_about_centroid(C, volume, m.centroid);
  return m;
}

}  // namespace

MassProperties mass_properties(const Region& region, int dimension) {
  if (dimension == 2 && region.shape == Shape::polygon) return polygon(region);
  if (dimension == 3 && region.shape == Shape::mesh) return mesh(region);
  return box(region, dimension);
}

}  // namespace sluice
