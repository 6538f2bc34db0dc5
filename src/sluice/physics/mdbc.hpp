// The modified dynamic boundary condition (mDBC) of English et al. (2022, Comp. Part. Mech. 9:1), as
// DualSPHysics 5 uses it. The wall particles are the dynamic boundary's layers, but their density is
// not integrated: before each force evaluation it is read off the water at the particle's ghost node,
// its mirror image through the wall surface (geometry/wall_ghosts.hpp), with a first-order
// correction,
//   rho_w = rho_g + (x_w - x_g) . grad rho_g,
// rho_g and grad rho_g the linear fit (core/linear_fit.hpp) to the fluid's densities around the ghost
// with the weights V_j W(|x_j - x_g|), V_j = m / rho_j. The wall so carries the pressure the water
// would have there, hydrostatic gradient included, and the water sits against it at dx/2 from the
// surface instead of a spacing or more off it (the dynamic boundary's gap). English et al. solve the
// kernel-gradient corrected system; the least-squares fit is first-order consistent as well.
//
// Where the fit is ill-posed (too few fluid neighbours, or all in a line) or the ghost is not well
// inside water, the Shepard density at the ghost is used, carried to the wall particle by the
// hydrostatic pressure difference rho g . (x_w - x_g); rho_w = rho0 where the ghost has no fluid
// around it, or where no fluid particle lies within the wall particle's own support (then nothing
// reads it). rho_w is held at rho0 or above, so that a wall never pulls water onto itself (English et
// al. likewise).
//
// The velocity this gives a wall particle enters the viscous terms only (the continuity equation sees
// the wall move as it does, at rest or with its body: physics/wall_motion.hpp; with the mirrored
// velocity there too, the
// ghost-fluid way, the obstacle case ran to its end but still water settled 0.5 % denser at the floor —
// docs/physics.md, "Walls"). From the Shepard average v_g of the fluid velocity at the ghost and the
// wall's own velocity u (WallMotion; zero at rest): no slip, v_w = 2 u - v_g (the velocity is the
// wall's at the surface, halfway between ghost and wall particle); free slip, v_w = u + (v_g - u) -
// 2 ((v_g - u) . n) n (the tangential velocity relative to the wall carries over, the normal one is
// mirrored), n the unit normal along x_g - x_w. After the rates, a wall particle's velocity is its
// wall's own again (what frames show and the next evaluation starts from).
//
// The ghost nodes of a moving body's particles move with it: the solver keeps `ghosts` at the
// current pose.
//
// Each wall particle is computed by one thread over its ghost's neighbours in cell order, so the
// result does not depend on the thread count.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/linear_fit.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/geometry/wall_ghosts.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/fluid_sums.hpp"
#include "sluice/physics/wall_motion.hpp"

namespace sluice {

// The first-order fit is trusted only where the ghost lies well inside water: its kernel sum
// sum_j V_j W (1 inside, about 1/2 at a flat free surface) at least this. In a thin jet or spray the
// fit would extrapolate a few smoothing lengths from a handful of particles (measured: a wall
// particle at 2166 kg/m^3 under the run-up of the default dam break).
inline constexpr double kFirstOrderCompleteness = 0.5;

// What the water around a ghost node says of the wall particle mirrored there.
template <int Dim>
struct GhostReading {
  double density = 0.0;  // rho_w, before the rho0 floor
  Vec<Dim> velocity{};   // v_g (Shepard)
  bool found = false;    // any fluid within the support of the ghost
};

// The fit at ghost node `ghost` for the wall particle at `wall`, from the sums over the fluid around
// the ghost (physics/fluid_sums.hpp; h the smoothing length they were taken with).
template <int Dim>
GhostReading<Dim> read_ghost(const FluidSums<Dim>& sums, double h, const TaitEos& eos, const Vec<Dim>& gravity,
                             const Vec<Dim>& ghost, const Vec<Dim>& wall) {
  const LinearFit<Dim>& fit = sums.fit;
  GhostReading<Dim> g;
  g.found = fit.weight() > 0.0;
  if (!g.found) return g;
  g.velocity = (1.0 / fit.weight()) * sums.velocity;
  if (sums.neighbours > Dim && fit.weight() >= kFirstOrderCompleteness) {
    if (const auto coef = fit.solve()) {
      g.density = (*coef)[0];
      for (int d = 0; d < Dim; ++d) g.density += (*coef)[d + 1] * (wall[d] - ghost[d]) / h;
      // No denser than the densest water around the ghost plus the hydrostatic rise over the distance
      // to the wall particle: in a splash the fit can extrapolate wildly (measured: 2732 kg/m^3 at a
      // wall particle under the run-up of the obstacle case).
      const double rise = eos.rest_density * norm(gravity) * norm(wall - ghost) / (eos.sound_speed * eos.sound_speed);
      g.density = std::min(g.density, sums.densest + rise);
      return g;
    }
  }
  // Zeroth order: the Shepard density at the ghost, carried to the wall particle hydrostatically.
  const double rho_g = fit.shepard();
  g.density = eos.density(eos.pressure(rho_g) + rho_g * dot(gravity, wall - ghost));
  return g;
}

struct MdbcWalls {
  // The artificial viscosity acts between water and wall as between water particles, on the wall
  // velocity the slip condition gives. With no slip it so becomes a wall friction far above water's
  // (measured in `sluice validate`: the Buchner impact at t* = 3.69 instead of the data's 2.51);
  // without it between water and wall, the wall pressure is noisier (Buchner RMS 0.33 against
  // 0.27 with free slip). Free slip is the default.
  static constexpr bool fluid_wall_viscosity = true;

  std::shared_ptr<const void> ghosts;  // WallGhosts<Dim> of the run's dimension
  double mass = 0.0;                   // particle mass m
  WallSlip slip = WallSlip::free_slip;

  template <int Dim>
  static MdbcWalls of(WallGhosts<Dim> g, double mass, WallSlip slip) {
    return {std::make_shared<const WallGhosts<Dim>>(std::move(g)), mass, slip};
  }
  // Ghost nodes that their owner (the solver) moves with the walls.
  template <int Dim>
  static MdbcWalls of(std::shared_ptr<const WallGhosts<Dim>> g, double mass, WallSlip slip) {
    return {std::move(g), mass, slip};
  }

  template <int Dim, class Kernel>
  void before_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, const TaitEos& eos,
                    const std::type_identity_t<Vec<Dim>>& gravity, int threads,
                    const WallMotion<Dim>* motion = nullptr) const {
    const auto& g = *static_cast<const WallGhosts<Dim>*>(ghosts.get());
    const AnyKernel<Dim> any_kernel(kernel);
    FluidIndex fluid;
    fluid.build(p, threads, &grid);
    // The wall particles with a fluid particle within the pair loop's support, as it computes it
    // (physics/pair_loop-inl.hpp, rate_loop).
    const double reach2 = Kernel::support * Kernel::support * kernel.h * kernel.h;
    std::vector<std::uint8_t> reached(p.size(), 0);
    parallel::for_chunks(static_cast<long>(grid.cell_count()), threads, [&](long first, long last) {
      walls_reached<Dim>(p, grid, fluid, static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(last), reach2,
                         reached.data());
    });
    const bool moving_walls = motion != nullptr && motion->any;
    // Each iteration reads fluid particles and writes one wall particle: no races.
    parallel::for_each_dynamic(static_cast<long>(p.size()), threads, 256, [&](long i) {
      const auto w = static_cast<std::size_t>(i);
      if (p.kind[w] != Kind::wall) return;
      Vec<Dim> x{};
      for (int d = 0; d < Dim; ++d) x[d] = p.position[d][w];
      GhostReading<Dim> r;
      Vec<Dim> v{};
      // A wall particle with no fluid particle within its own support takes part in no pair with water
      // in this evaluation (nor in the Shepard filter's or shifting's sums): its ghost is not read, and
      // it holds rho0 and rest, as a dry wall does. Under water that is the deepest layer, whose ghost
      // node lies several spacings into the water, its sums as costly as any.
      if (g.of(p.id[w]) && reached[w] != 0) {
        const Vec<Dim>& ghost = g.node[p.id[w]];
        r = read_ghost<Dim>(fluid_sums_at<Dim>(p, grid, any_kernel, mass, fluid, ghost), kernel.h, eos, gravity, ghost, x);
        if (moving_walls && motion->moves(p.body[w])) {
          const Vec<Dim> u = motion->velocity(p, w);
          v = u;
          if (r.found && slip == WallSlip::no_slip) v = 2.0 * u - r.velocity;
          if (r.found && slip == WallSlip::free_slip) {
            const Vec<Dim> n = (1.0 / norm(ghost - x)) * (ghost - x);
            const Vec<Dim> relative = r.velocity - u;
            v = u + relative - (2.0 * dot(relative, n)) * n;
          }
        } else {
          if (r.found && slip == WallSlip::no_slip) v = -1.0 * r.velocity;
          if (r.found && slip == WallSlip::free_slip) {
            const Vec<Dim> n = (1.0 / norm(ghost - x)) * (ghost - x);
            v = r.velocity - (2.0 * dot(r.velocity, n)) * n;
          }
        }
      } else if (moving_walls) {
        v = motion->velocity(p, w);
      }
      p.density[w] = r.found ? std::max(r.density, eos.rest_density) : eos.rest_density;
      for (int d = 0; d < Dim; ++d) p.velocity[d][w] = v[d];
    });
  }
  template <int Dim>
  void after_rates(Particles<Dim>& p, int threads, const WallMotion<Dim>* motion = nullptr) const {
    const bool moving_walls = motion != nullptr && motion->any;
    parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
      for (long i = begin; i < end; ++i) {
        const auto w = static_cast<std::size_t>(i);
        if (p.is_fluid(w)) continue;
        p.density_rate[w] = 0.0;
        const Vec<Dim> u = moving_walls ? motion->velocity(p, w) : Vec<Dim>{};
        for (int d = 0; d < Dim; ++d) p.velocity[d][w] = u[d];
      }
    });
  }
};

}  // namespace sluice
