// The rates of the WCSPH equations (accelerations and density rates) and the Shepard density filter,
// computed by the pair loop of physics/pair_loop-inl.hpp. That loop is compiled once per instruction
// set (SSE4, AVX2, AVX-512, NEON, ... and a portable fallback), and the best one the CPU runs is
// chosen when the program starts (physics/simd_target.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/particle_terms.hpp"
#include "sluice/physics/walls.hpp"

namespace sluice {

template <int Dim>
struct RateSettings {
  double mass;          // particle mass m
  double h;             // smoothing length
  double viscosity;     // mu
  double alpha;         // artificial viscosity
  double delta;         // density diffusion
  Vec<Dim> gravity;
  TaitEos eos;
  double artificial_pressure = 0.0;  // Monaghan (2000) epsilon; 0 = off
  int artificial_pressure_exponent = 4;
  double spacing = 0.0;              // dx, for W(dx) in the artificial pressure
  // The least P/rho^2 either particle of a fluid-wall pair brings to the pair's pressure force: -inf
  // (none, the default) or 0, where walls cannot hold the water in tension (physics.wall_tension = false).
  double wall_pair_pressure_floor = -std::numeric_limits<double>::infinity();
};

struct RateSummary {
  double max_acceleration = 0.0;    // over fluid particles, including gravity
  double max_relative_speed = 0.0;  // max |v_ij| over interacting pairs with a fluid particle
  double max_density = 0.0;         // over all particles
  double min_fluid_distance = 0.0;  // smallest distance from a fluid particle to any other (clumping)
};

// What the sums of particle shifting need (physics/shifting.hpp).
struct ShiftingSums {
  double h = 0.0;        // smoothing length
  double spacing = 0.0;  // dx
  double volume = 0.0;   // dx^Dim
  double tensile = 0.2;  // R of Sun et al. (2017)
  int exponent = 4;      // n
};

// Fills p.acceleration (fluid particles, gravity included; wall entries are scratch) and
// p.density_rate (all particles) from the pair interactions of every pair within the kernel support.
// `terms` must be computed on the current densities, and `grid` binned on the current particle order.
// The results are the same bit for bit on any number of threads.
template <int Dim>
RateSummary compute_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                          const WallTreatment& walls, const RateSettings<Dim>& settings, const ParticleTerms& terms,
                          int threads);

// Shepard density filter (the sum includes i = j): rho_i = sum_j m W_ij / sum_j (m/rho_j) W_ij, for
// the fluid particles i with selected[i] != 0, or for all fluid particles when `selected` is null.
// `scratch` is resized to the particle count.
template <int Dim>
void shepard_filter(Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel, double mass,
                    const std::vector<std::uint8_t>* selected, std::vector<double>& scratch, int threads);

// The sums of particle shifting over every pair, fluid and wall particles alike (physics/
// shifting_pair-inl.hpp): out[0, Dim) = grad C, out[Dim, 2 Dim) = grad C^R, out[2 Dim] = div r, each
// of the particle count. `fluid` is 1 for fluid, 0 for wall particles; `grid` binned on the current
// order. The same bit for bit on any number of threads.
template <int Dim>
void shifting_sums(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                   const ShiftingSums& settings, const double* fluid, const std::array<double*, 2 * Dim + 1>& out,
                   int threads);

// The sums of the renormalised density gradient over the fluid-fluid pairs (physics/
// density_gradient_pair-inl.hpp): out[0, Dim(Dim+1)/2) = the upper triangle of M row by row,
// then g, each of the particle count. `fluid` is 1 for fluid, 0 for wall particles;
// `grid` binned on the current order. The same bit for bit on any number of threads.
template <int Dim>
void density_gradient_sums(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                           double mass, const double* fluid,
                           const std::array<double*, Dim*(Dim + 1) / 2 + Dim>& out, int threads);

extern template RateSummary compute_rates<2>(Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&,
                                             const WallTreatment&, const RateSettings<2>&, const ParticleTerms&, int);
extern template RateSummary compute_rates<3>(Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&,
                                             const WallTreatment&, const RateSettings<3>&, const ParticleTerms&, int);
extern template void shepard_filter<2>(Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, double,
                                       const std::vector<std::uint8_t>*, std::vector<double>&, int);
extern template void shifting_sums<2>(const Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&,
                                      const ShiftingSums&, const double*, const std::array<double*, 5>&, int);
extern template void shifting_sums<3>(const Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&,
                                      const ShiftingSums&, const double*, const std::array<double*, 7>&, int);
extern template void shepard_filter<3>(Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, double,
                                       const std::vector<std::uint8_t>*, std::vector<double>&, int);

}  // namespace sluice
