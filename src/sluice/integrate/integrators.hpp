// Time integrators. Fluid particles move; wall particles keep position and velocity while their
// density evolves like the fluid's. A wall's density is not allowed below rho0 (a floor, as in
// DualSPHysics' dynamic boundaries) so a wall never pulls fluid towards itself.
#pragma once

#include <algorithm>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"

namespace sluice {

// Forward Euler: y(n+1) = y(n) + dt f(y(n)), using the rates of the current state.
template <int Dim>
void euler_update(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) {
      if (p.is_fluid(static_cast<std::size_t>(i))) {
        for (int d = 0; d < Dim; ++d) {
          p.position[d][i] += dt * p.velocity[d][i];
          p.velocity[d][i] += dt * p.acceleration[d][i];
        }
        p.density[i] += dt * p.density_rate[i];
      } else {
        p.density[i] = std::max(p.density[i] + dt * p.density_rate[i], wall_density_floor);
      }
    }
  });
}

// Predictor-corrector (midpoint), stage 1: remember y(n), then y(n+1/2) = y(n) + dt/2 f(y(n)).
template <int Dim>
void predictor_update(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  for (int d = 0; d < Dim; ++d) {
    p.position_start[d] = p.position[d];
    p.velocity_start[d] = p.velocity[d];
  }
  p.density_start = p.density;
  euler_update(p, 0.5 * dt, wall_density_floor, threads);
}

// Stage 2, with the rates f(y(n+1/2)) evaluated at the half step: the corrected half step
// ybar = y(n) + dt/2 f(y(n+1/2)) is extrapolated to y(n+1) = 2 ybar - y(n) = y(n) + dt f(y(n+1/2)).
template <int Dim>
void corrector_update(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) {
      if (p.is_fluid(static_cast<std::size_t>(i))) {
        for (int d = 0; d < Dim; ++d) {
          p.position[d][i] = p.position_start[d][i] + dt * p.velocity[d][i];
          p.velocity[d][i] = p.velocity_start[d][i] + dt * p.acceleration[d][i];
        }
        p.density[i] = p.density_start[i] + dt * p.density_rate[i];
      } else {
        p.density[i] = std::max(p.density_start[i] + dt * p.density_rate[i], wall_density_floor);
      }
    }
  });
}

}  // namespace sluice
