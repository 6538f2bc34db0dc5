#include "sluice/geometry/setup.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"

namespace sluice {

int wall_layers(const Case& c) {
  return std::max(1, static_cast<int>(std::ceil(2.0 * c.smoothing_length() / c.dx - 1e-9)));
}

namespace {

// Lattice points anchor + (i + 1/2) dx along one axis, for those strictly inside (lo, hi).
std::vector<double> lattice(double anchor, double lo, double hi, double dx) {
  std::vector<double> v;
  const long first = static_cast<long>(std::floor((lo - anchor) / dx - 0.5));
  const long last = static_cast<long>(std::ceil((hi - anchor) / dx - 0.5));
  for (long i = first; i <= last; ++i) {
    const double x = anchor + (static_cast<double>(i) + 0.5) * dx;
    if (x > lo && x < hi) v.push_back(x);
  }
  return v;
}

void add_tank(Setup& s, const Case& c) {
  const double dx = c.dx;
  const double depth = wall_layers(c) * dx;
  const double w = c.tank_width;
  const double h = c.tank_height;
  auto add_points = [&](const std::vector<double>& xs, const std::vector<double>& ys) {
    for (double y : ys)
      for (double x : xs) s.particles.add({x, y}, Kind::wall, c.rest_density);
  };
  // Each wall's layers are anchored at its own inner face, so the first layer sits dx/2 behind it.
  const auto columns = lattice(0.0, -depth, w + depth, dx);
  add_points(columns, lattice(0.0, -depth, 0.0, dx));
  add_points(lattice(0.0, -depth, 0.0, dx), lattice(0.0, 0.0, h, dx));
  add_points(lattice(w, w, w + depth, dx), lattice(0.0, 0.0, h, dx));
  s.solids.push_back(Polygon::box({-depth, -depth}, {w + depth, 0.0}));
  s.solids.push_back(Polygon::box({-depth, 0.0}, {0.0, h}));
  s.solids.push_back(Polygon::box({w, 0.0}, {w + depth, h}));
  if (c.tank_lid) {
    add_points(columns, lattice(h, h, h + depth, dx));
    s.solids.push_back(Polygon::box({-depth, h}, {w + depth, h + depth}));
  }
  s.domain_lower = {-depth, -depth};
  s.domain_upper = {w + depth, h + depth};
}

Polygon region_polygon(const Region& r) {
  return r.shape == "polygon" ? Polygon{r.points} : Polygon::box(r.min, r.max);
}

// Fills a solid polygon with wall particles to a depth of `layers` x dx inside its outline: rows
// parallel to each edge at depths (k + 1/2) dx, spaced about dx along the edge, and arcs of the same
// depths around each reflex corner (where the solid wraps around the water and the rows of the two
// edges leave a wedge empty). Points closer than dx/2 to each other are thinned out afterwards.
void add_solid(Setup& s, const Case& c, const Polygon& solid) {
  const double dx = c.dx;
  const int layers = wall_layers(c);
  const std::size_t n = solid.points.size();
  double twice_area = 0.0;
  for (std::size_t k = 0, j = n - 1; k < n; j = k++)
    twice_area += solid.points[j][0] * solid.points[k][1] - solid.points[k][0] * solid.points[j][1];
  const double orientation = twice_area > 0.0 ? 1.0 : -1.0;  // +1: counter-clockwise
  auto edge = [&](std::size_t k) {
    const Vec2 a = solid.points[k], b = solid.points[(k + 1) % n];
    const double length = norm(b - a);
    const Vec2 tangent = (1.0 / length) * (b - a);
    const Vec2 inward = orientation * Vec2{-tangent[1], tangent[0]};  // into the solid
    return std::tuple{a, length, tangent, inward};
  };
  auto add = [&](Vec2 p) {
    if (solid.contains(p)) s.particles.add(p, Kind::wall, c.rest_density);
  };
  for (std::size_t k = 0; k < n; ++k) {
    const auto [a, length, tangent, inward] = edge(k);
    if (length <= 0.0) continue;
    const int along = std::max(1, static_cast<int>(std::lround(length / dx)));
    const double spacing = length / along;
    for (int layer = 0; layer < layers; ++layer) {
      const double depth = (layer + 0.5) * dx;
      for (int j = 0; j < along; ++j) add(a + ((j + 0.5) * spacing) * tangent + depth * inward);
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
        add(vertex + radius * Vec2{std::cos(angle), std::sin(angle)});
      }
    }
  }
  s.solids.push_back(solid);
}

// Water on the lattice (i + 1/2) dx inside the region, outside every solid and at least dx/2 from
// every solid surface (so at least dx from the first wall layer).
void add_water(Setup& s, const Case& c, const Region& r) {
  const Polygon region = region_polygon(r);
  const double tol = 1e-9 * c.dx;
  const Vec2 lo = region.lower(), hi = region.upper();
  for (double y : lattice(0.0, lo[1] - tol, hi[1] + tol, c.dx))
    for (double x : lattice(0.0, lo[0] - tol, hi[0] + tol, c.dx)) {
      const Vec2 p{x, y};
      if (!region.contains(p)) continue;
      const bool blocked = std::any_of(s.solids.begin(), s.solids.end(), [&](const Polygon& q) {
        return q.contains(p) || q.distance_to_boundary(p) < 0.5 * c.dx - tol;
      });
      if (!blocked) s.particles.add(p, Kind::fluid, c.rest_density);
    }
}

}  // namespace

std::size_t remove_near_coincident(Particles<2>& p, double min_distance) {
  const std::size_t n = p.size();
  if (n == 0) return 0;
  Vec2 lo{p.position[0][0], p.position[1][0]}, hi = lo;
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], p.position[d][i]);
      hi[d] = std::max(hi[d], p.position[d][i]);
    }
  // Cells of twice the distance: a neighbour within it is in an adjacent cell, and the cell array stays
  // small over the air of a mostly empty tank.
  CellGrid<2> grid(lo, hi, 2.0 * min_distance);
  grid.bin(p.position);
  const auto& order = grid.order();  // sorted index k holds particle order[k]
  std::vector<std::uint8_t> removed(n, 0);
  const double min2 = min_distance * min_distance;
  // Visit walls first so that a wall point always wins over a fluid point; otherwise the lower index wins.
  for (Kind pass : {Kind::wall, Kind::fluid}) {
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t i = order[k];
      if (p.kind[i] != pass || removed[i]) continue;
      grid.for_each_neighbor_range(grid.cell_of()[k], [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t kj = begin; kj < end; ++kj) {
          const std::uint32_t j = order[kj];
          if (j == i || removed[j]) continue;
          if (p.kind[j] == Kind::wall && pass == Kind::fluid) continue;
          if (p.kind[j] == pass && j < i) continue;
          const double dx = p.position[0][i] - p.position[0][j];
          const double dy = p.position[1][i] - p.position[1][j];
          if (dx * dx + dy * dy < min2) removed[j] = 1;
        }
      });
    }
  }
  std::vector<std::uint32_t> keep;
  for (std::uint32_t i = 0; i < n; ++i)
    if (!removed[i]) keep.push_back(i);
  const std::size_t count = n - keep.size();
  Particles<2> out;
  out.resize(keep.size());
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const std::uint32_t i = keep[k];
    for (int d = 0; d < 2; ++d) {
      out.position[d][k] = p.position[d][i];
      out.velocity[d][k] = p.velocity[d][i];
    }
    out.density[k] = p.density[i];
    out.kind[k] = p.kind[i];
    out.id[k] = static_cast<std::uint32_t>(k);
  }
  p = std::move(out);
  return count;
}

void set_hydrostatic_density(Particles<2>& p, const Case& c) {
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  const double g = -c.gravity[1];
  if (g <= 0.0) return;
  // Free-surface height over each lattice column: top of the highest fluid particle in it.
  std::map<long, double> surface;
  auto column = [&](double x) { return static_cast<long>(std::floor(x / c.dx)); };
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) continue;
    const long col = column(p.position[0][i]);
    const double top = p.position[1][i] + 0.5 * c.dx;
    auto [it, inserted] = surface.emplace(col, top);
    if (!inserted) it->second = std::max(it->second, top);
  }
  if (surface.empty()) return;
  const long reach = wall_layers(c) + 1;  // walls beside the water take the nearest column's surface
  for (std::size_t i = 0; i < p.size(); ++i) {
    const long col = column(p.position[0][i]);
    auto it = surface.find(col);
    for (long off = 1; it == surface.end() && off <= reach; ++off) {
      it = surface.find(col - off);
      if (it == surface.end()) it = surface.find(col + off);
    }
    if (it == surface.end()) continue;
    const double depth = it->second - p.position[1][i];
    if (depth > 0.0) p.density[i] = eos.density(c.rest_density * g * depth);
  }
}

Setup build_setup(const Case& c) {
  Setup s;
  add_tank(s, c);
  for (const Region& r : c.walls) add_solid(s, c, region_polygon(r));
  for (const Region& r : c.water) add_water(s, c, r);
  s.removed_near_coincident = remove_near_coincident(s.particles, 0.5 * c.dx);
  if (c.hydrostatic_start) set_hydrostatic_density(s.particles, c);
  if (c.initial_pressure != 0.0) {
    const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
    const double floor = -0.99 * eos.stiffness();  // the lowest pressure the Tait equation can represent
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (s.particles.is_fluid(i))
        s.particles.density[i] = eos.density(std::max(eos.pressure(s.particles.density[i]) + c.initial_pressure, floor));
  }
  return s;
}

}  // namespace sluice
