#include "sluice/geometry/wall_ghosts.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>

#include "sluice/geometry/box.hpp"
#include "sluice/geometry/setup.hpp"

namespace sluice {

template <int Dim>
WallGhosts<Dim> wall_ghosts(const Particles<Dim>& p, const Case& c) {
  constexpr int up = Dim - 1;
  const Vec3 size = c.tank_size();
  Vec<Dim> inside_lo{}, inside_hi{};
  for (int d = 0; d < Dim; ++d) inside_hi[d] = size[d];
  if (!c.tank_lid) inside_hi[up] = std::numeric_limits<double>::infinity();
  // The fixed walls' regions, which water cannot be in; each moving wall's shape, at the start.
  std::vector<std::shared_ptr<const Solid<Dim>>> regions, moving(c.walls.size());
  for (std::size_t k = 0; k < c.walls.size(); ++k) {
    if (c.walls[k].moves()) moving[k] = region_solid<Dim>(c.walls[k]);
    else regions.push_back(region_solid<Dim>(c.walls[k]));
  }
  const double step = 1e-3 * c.dx;  // "just past q"

  auto in_tank = [&](const Vec<Dim>& x) {
    for (int d = 0; d < Dim; ++d)
      if (!(x[d] > inside_lo[d] && x[d] < inside_hi[d])) return false;
    return true;
  };
  auto is_water_side = [&](const Vec<Dim>& x, const Vec<Dim>& q) {
    const Vec<Dim> away = q - x;
    const double len = norm(away);
    if (!(len > 0.0)) return false;
    const Vec<Dim> past = q + (step / len) * away;
    return in_tank(past) && std::none_of(regions.begin(), regions.end(), [&](const auto& s) { return s->contains(past); });
  };

  WallGhosts<Dim> g;
  std::uint32_t max_id = 0;
  for (std::size_t i = 0; i < p.size(); ++i) max_id = std::max(max_id, p.id[i]);
  g.node.assign(p.size() == 0 ? 0 : max_id + 1, Vec<Dim>{});
  g.has.assign(g.node.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_fluid(i)) continue;
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = p.position[d][i];
    double best = std::numeric_limits<double>::infinity();
    Vec<Dim> nearest{};
    const std::function<void(const Vec<Dim>&)> consider = [&](const Vec<Dim>& q) {
      const double dist = norm(q - x);
      if (dist < best && is_water_side(x, q)) best = dist, nearest = q;
    };
    // A moving wall's particle is mirrored through its own surface only; the others' through the
    // tank's and the fixed walls' (a moving wall passes by them).
    const std::size_t k = p.body[i] - std::size_t{body_id::first_wall};
    if (p.body[i] >= body_id::first_wall && k < moving.size() && moving[k]) {
      moving[k]->for_each_face_point(x, consider);
    } else if (p.body[i] == body_id::tank && c.tank_moves()) {
      for_each_box_face_point<Dim>(inside_lo, inside_hi, x, consider);  // a moving tank: through its own faces
    } else {
      for_each_box_face_point<Dim>(inside_lo, inside_hi, x, consider);
      for (const auto& s : regions) s->for_each_face_point(x, consider);
    }
    if (best == std::numeric_limits<double>::infinity()) continue;
    g.node[p.id[i]] = 2.0 * nearest - x;
    g.has[p.id[i]] = 1;
  }
  return g;
}

template WallGhosts<2> wall_ghosts<2>(const Particles<2>&, const Case&);
template WallGhosts<3> wall_ghosts<3>(const Particles<3>&, const Case&);

}  // namespace sluice
