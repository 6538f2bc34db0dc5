// Wall treatments as policies. A policy says what the pair loop does between fluid and wall particles
// (its traits, read by the WCSPH pair of physics/wcsph_pair-inl.hpp) and what happens to the wall
// particles before and after the rates are computed. The pair loop is compiled for each policy of
// WallTreatment (physics/pair_loop-inl.hpp).
//
// A new wall treatment is a policy here, an alternative of WallTreatment (and of the case's
// WallBoundary choice), and — if it changes a pair term — its trait in WallPairTraits, read in
// wcsph_pair-inl.hpp.
#pragma once

#include <type_traits>
#include <variant>

#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/mdbc.hpp"
#include "sluice/physics/wall_boundary.hpp"

namespace sluice {

// Dynamic boundary particles (Crespo et al. 2007): wall particles obey the continuity equation like
// the fluid, their density (so pressure) rises as the fluid approaches, and fluid-wall pairs feel the
// artificial viscosity like fluid-fluid pairs. A wall particle's velocity is its wall's own (zero at
// rest, or as its body moves: the solver sets it), which the viscosity sees, and the continuity
// equation through add_moving_wall_continuity (physics/wall_motion.hpp).
struct DynamicWalls {
  static constexpr bool fluid_wall_viscosity = true;

  template <int Dim, class Kernel>
  void before_rates(Particles<Dim>&, const CellGrid<Dim>&, const Kernel&, const TaitEos&,
                    const std::type_identity_t<Vec<Dim>>&, int, const WallMotion<Dim>* = nullptr) const {}
  template <int Dim>
  void after_rates(Particles<Dim>&, int, const WallMotion<Dim>* = nullptr) const {}
};

// Adami, Hu & Adams (2012) generalized walls: the wall density is set from the pressure extrapolated
// from the fluid (physics/wall_boundary.hpp) just before the pair loop, and not integrated (its rate
// is zeroed); free slip, so no artificial viscosity between fluid and wall. A moving wall's
// acceleration enters the extrapolation; its velocity, the continuity equation (wall_motion.hpp).
struct AdamiWalls {
  static constexpr bool fluid_wall_viscosity = false;

  template <int Dim, class Kernel>
  void before_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, const TaitEos& eos,
                    const std::type_identity_t<Vec<Dim>>& gravity, int threads,
                    const WallMotion<Dim>* motion = nullptr) const {
    extrapolate_wall_density(p, grid, kernel, eos, gravity, threads, motion);
  }
  template <int Dim>
  void after_rates(Particles<Dim>& p, int threads, const WallMotion<Dim>* = nullptr) const {
    parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
      for (long i = begin; i < end; ++i)
        if (!p.is_fluid(static_cast<std::size_t>(i))) p.density_rate[i] = 0.0;
    });
  }
};

// In the order of the case's WallBoundary choices; mDBC is in physics/mdbc.hpp.
using WallTreatment = std::variant<DynamicWalls, AdamiWalls, MdbcWalls>;

// What the pair interaction reads of a wall treatment. The pair loop is compiled once per set of
// these traits, not once per treatment: mDBC's pairs are the dynamic boundary's.
template <bool FluidWallViscosity>
struct WallPairTraits {
  static constexpr bool fluid_wall_viscosity = FluidWallViscosity;
};
using PairWallTraits = std::variant<WallPairTraits<true>, WallPairTraits<false>>;

// The index in PairWallTraits of a treatment's traits.
inline std::size_t pair_traits_index(const WallTreatment& walls) {
  return std::visit([](const auto& w) -> std::size_t { return std::decay_t<decltype(w)>::fluid_wall_viscosity ? 0 : 1; },
                    walls);
}

}  // namespace sluice
