// Generalized wall boundary conditions after Adami, Hu & Adams (2012), J. Comput. Phys. 231, 7057:
// the pressure of each wall particle w is extrapolated from the fluid particles f within its kernel
// support,
//   p_w = [ sum_f p_f W_wf + (g - a_w) . sum_f rho_f r_wf W_wf ] / sum_f W_wf,   r_wf = x_w - x_f,
// with a_w the wall's acceleration (WallMotion; zero for a fixed wall), and the wall density is set from the inverted Tait equation,
// rho_w = rho0 (p_w / B + 1)^(1/gamma), so that the pair loop sees that pressure through P/rho^2.
// A wall particle with no fluid neighbour gets p = 0 (rho = rho0); a negative extrapolated pressure
// is clamped to 0 (it would pull the fluid into the wall). The wall velocity is not extrapolated
// (free slip): the fluid-wall artificial viscosity is switched off instead (AdamiWalls, walls.hpp).
//
// Each wall particle is summed by one thread over its neighbours in a fixed (cell) order, so the
// results do not depend on the number of threads.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/wall_motion.hpp"

namespace sluice {

// The extrapolated (unclamped) pressure of wall particle w, `gravity` less the wall's acceleration;
// `found` tells whether it has fluid neighbours within the support. Requires a grid binned on the
// current (sorted) particles.
template <int Dim, class Kernel>
double extrapolated_wall_pressure(const Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel,
                                  const TaitEos& eos, const std::type_identity_t<Vec<Dim>>& gravity, std::size_t w,
                                  bool& found) {
  const double support2 = Kernel::support * Kernel::support * kernel.h * kernel.h;
  double sum_w = 0.0, sum_pw = 0.0;
  std::array<double, Dim> sum_rho_r{};
  grid.for_each_neighbor_range(grid.cell_of()[w], [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t f = begin; f < end; ++f) {
      if (p.kind[f] != Kind::fluid) continue;
      std::array<double, Dim> r{};
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        r[d] = p.position[d][w] - p.position[d][f];
        r2 += r[d] * r[d];
      }
      if (r2 >= support2) continue;
      const double wf = kernel.value(std::sqrt(r2));
      const double rho_f = p.density[f];
      sum_w += wf;
      sum_pw += eos.pressure(rho_f) * wf;
      for (int d = 0; d < Dim; ++d) sum_rho_r[d] += rho_f * r[d] * wf;
    }
  });
  found = sum_w > 0.0;
  if (!found) return 0.0;
  double g_dot = 0.0;
  for (int d = 0; d < Dim; ++d) g_dot += gravity[d] * sum_rho_r[d];  // (g - a_w)
  return (sum_pw + g_dot) / sum_w;
}

// Sets the density of every wall particle from its extrapolated pressure (clamped at 0), its wall's
// acceleration from `motion` (without it, all walls at rest). The grid must be binned on the current
// particle order.
template <int Dim, class Kernel>
void extrapolate_wall_density(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, const TaitEos& eos,
                              const std::type_identity_t<Vec<Dim>>& gravity, int threads,
                              const WallMotion<Dim>* motion = nullptr) {
  // Each iteration reads fluid densities and writes one wall density only: no races.
  parallel::for_each_dynamic(static_cast<long>(p.size()), threads, 256, [&](long i) {
    const auto w = static_cast<std::size_t>(i);
    if (p.kind[w] != Kind::wall) return;
    bool found = false;
    const bool moves = motion != nullptr && motion->any && motion->moves(p.body[w]);
    const Vec<Dim> g = moves ? gravity - motion->acceleration(p, w) : gravity;
    const double pressure = extrapolated_wall_pressure(p, grid, kernel, eos, g, w, found);
    p.density[w] = found ? eos.density(std::max(pressure, 0.0)) : eos.rest_density;
  });
}

}  // namespace sluice
