// Time integrators. Fluid particles move; wall particles keep position and velocity while their
// density evolves like the fluid's. A wall's density is not allowed below rho0 (a floor, as in
// DualSPHysics' dynamic boundaries) so a wall never pulls fluid towards itself.
#pragma once

#include <algorithm>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"

namespace sluice {

// Forward Euler on the particles [begin, end): y(n+1) = y(n) + dt f(y(n)).
template <int Dim>
void euler_chunk(Particles<Dim>& p, double dt, double wall_density_floor, long begin, long end) {
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
}

// Forward Euler: y(n+1) = y(n) + dt f(y(n)), using the rates of the current state.
template <int Dim>
void euler_update(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  parallel::for_chunks(static_cast<long>(p.size()), threads,
                       [&](long begin, long end) { euler_chunk(p, dt, wall_density_floor, begin, end); });
}

// Predictor-corrector (midpoint), stage 1: remember y(n), then y(n+1/2) = y(n) + dt/2 f(y(n)).
// Each thread copies its share of y(n) and updates it in one pass.
template <int Dim>
void predictor_update(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  const std::size_t n = p.size();
  for (int d = 0; d < Dim; ++d) {
    p.position_start[d].resize(n);
    p.velocity_start[d].resize(n);
  }
  p.density_start.resize(n);
  parallel::for_chunks(static_cast<long>(n), threads, [&](long begin, long end) {
    const auto copy = [begin, end](const std::vector<double>& from, std::vector<double>& to) {
      std::copy(from.begin() + begin, from.begin() + end, to.begin() + begin);
    };
    for (int d = 0; d < Dim; ++d) {
      copy(p.position[d], p.position_start[d]);
      copy(p.velocity[d], p.velocity_start[d]);
    }
    copy(p.density, p.density_start);
    euler_chunk(p, 0.5 * dt, wall_density_floor, begin, end);
  });
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

// Leapfrog: kick-drift-kick (velocity Verlet), one force evaluation per step. With a(n), D(n) the
// acceleration and density rate of the state y(n) (evaluated at the end of the previous step and
// carried into this one):
//   kick + drift   v(n+1/2) = v(n) + dt/2 a(n),  rho(n+1/2) = rho(n) + dt/2 D(n),
//                  x(n+1) = x(n) + dt v(n+1/2);
//   predict        v* = v(n+1/2) + dt/2 a(n),  rho* = rho(n+1/2) + dt/2 D(n)   (= v(n) + dt a(n), ...);
//   evaluate       a(n+1), D(n+1) = f(x(n+1), v*, rho*)           (Solver::step, its one evaluation);
//   final kick     v(n+1) = v(n+1/2) + dt/2 a(n+1),  rho(n+1) = rho(n+1/2) + dt/2 D(n+1),
// and a(n+1), D(n+1) are kept for the next step. Positions are second order and time-reversible (for
// forces of the positions alone); the velocity-dependent terms (viscosity, density diffusion) and
// the density see the first-order prediction v*, rho*.
//
// The final kick is written from the predicted values, v(n+1) = v* + dt/2 (a(n+1) - a(n)) (the same
// number up to rounding), so that what the evaluation did to the state it evaluated carries over:
// the Shepard filter and the density repair of a put-back particle rewrite rho* there, and the Adami
// and mDBC walls their own densities (their density rate is 0, so the wall keeps the evaluated one).
// Wall particles keep position and velocity; their density evolves with the floor, as above.

// Stage 1 for particle i: saves y(n) and a(n), D(n) to the step-start fields (the instability guard's
// way back; the evaluation's reordering moves them), then kick, drift and predict: the particle holds
// x(n+1), v*, rho*. On entry the rates a(n), D(n) are in acceleration_start and density_rate_start.
// One particle at a time, for the solver's sweep that does more with each (the wall checks).
template <int Dim>
inline void leapfrog_kick_drift_one(Particles<Dim>& p, long i, double dt, double wall_density_floor) {
  const double half = 0.5 * dt;
  p.density_start[i] = p.density[i];
  for (int d = 0; d < Dim; ++d) {
    p.position_start[d][i] = p.position[d][i];
    p.velocity_start[d][i] = p.velocity[d][i];
  }
  const double rate = p.density_rate_start[i];
  if (p.is_fluid(static_cast<std::size_t>(i))) {
    for (int d = 0; d < Dim; ++d) {
      const double a = p.acceleration_start[d][i];
      const double v_half = p.velocity[d][i] + half * a;
      p.position[d][i] += dt * v_half;
      p.velocity[d][i] = v_half + half * a;
    }
    p.density[i] = (p.density[i] + half * rate) + half * rate;
  } else {
    const double rho_half = std::max(p.density[i] + half * rate, wall_density_floor);
    p.density[i] = std::max(rho_half + half * rate, wall_density_floor);
  }
}

// Stage 1 for every particle.
template <int Dim>
void leapfrog_kick_drift(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) leapfrog_kick_drift_one(p, i, dt, wall_density_floor);
  });
}

// Stage 2 for particle i, with a(n+1), D(n+1) in acceleration and density_rate (evaluated at x(n+1),
// v*, rho*) and a(n), D(n) in acceleration_start and density_rate_start, in the same (reordered)
// order: v(n+1) = v* + dt/2 (a(n+1) - a(n)), rho(n+1) = rho* + dt/2 (D(n+1) - D(n)).
template <int Dim>
inline void leapfrog_final_kick_one(Particles<Dim>& p, long i, double dt, double wall_density_floor) {
  const double half = 0.5 * dt;
  const double rho = p.density[i] + half * (p.density_rate[i] - p.density_rate_start[i]);
  if (p.is_fluid(static_cast<std::size_t>(i))) {
    for (int d = 0; d < Dim; ++d) p.velocity[d][i] += half * (p.acceleration[d][i] - p.acceleration_start[d][i]);
    p.density[i] = rho;
  } else {
    p.density[i] = std::max(rho, wall_density_floor);
  }
}

// Stage 2 for every particle.
template <int Dim>
void leapfrog_final_kick(Particles<Dim>& p, double dt, double wall_density_floor, int threads) {
  parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) leapfrog_final_kick_one(p, i, dt, wall_density_floor);
  });
}

}  // namespace sluice
