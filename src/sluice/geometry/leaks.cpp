#include "sluice/core/parallel.hpp"
#include "sluice/geometry/leaks.hpp"

#include <algorithm>

namespace sluice {

namespace {

struct SolidBox {
  const Polygon* polygon;
  Vec2 lower, upper;
};

const Polygon* containing(const std::vector<SolidBox>& boxes, Vec2 x) {
  for (const SolidBox& b : boxes)
    if (x[0] > b.lower[0] && x[0] < b.upper[0] && x[1] > b.lower[1] && x[1] < b.upper[1] && b.polygon->contains(x))
      return b.polygon;
  return nullptr;
}

}  // namespace

std::size_t put_back_leaked(Particles<2>& p, const std::vector<Polygon>& solids, double dx, int threads) {
  std::vector<SolidBox> boxes;
  boxes.reserve(solids.size());
  for (const Polygon& s : solids) boxes.push_back({&s, s.lower(), s.upper()});

  long count = 0;
  const long n = static_cast<long>(p.size());
#pragma omp parallel for num_threads(threads) schedule(static) reduction(+ : count) if (n >= light_loop_parallel_threshold)
  for (long i = 0; i < n; ++i) {
    if (p.kind[i] != Kind::fluid) continue;
    Vec2 x{p.position[0][i], p.position[1][i]};
    const Polygon* solid = containing(boxes, x);
    if (solid == nullptr) continue;
    ++count;
    Vec2 v{p.velocity[0][i], p.velocity[1][i]};
    // A few passes: put back across one wall face may land inside an adjoining wall at a corner.
    for (int pass = 0; pass < 4 && solid != nullptr; ++pass) {
      const Vec2 surface = solid->closest_boundary_point(x);
      Vec2 normal = surface - x;
      const double len = norm(normal);
      if (len < 1e-12 * dx) break;  // on the surface already
      normal = (1.0 / len) * normal;
      x = surface + (0.5 * dx) * normal;
      const double vn = dot(v, normal);
      if (vn < 0.0) v = v - (2.0 * vn) * normal;
      solid = containing(boxes, x);
    }
    p.position[0][i] = x[0];
    p.position[1][i] = x[1];
    p.velocity[0][i] = v[0];
    p.velocity[1][i] = v[1];
    p.needs_density_repair[i] = 1;
  }
  return static_cast<std::size_t>(count);
}

}  // namespace sluice
