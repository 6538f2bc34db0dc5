// Wall friction from the log law of the wall (a wall function), for walls without friction of their
// own (mDBC with free slip, Adami walls). SPH at engineering resolutions does not resolve the boundary
// layer: the first water sits dx/2 off the wall, far outside the viscous sublayer, so no-slip walls
// with a viscosity (artificial, or water's) give a friction set by the particle spacing and the
// artificial viscosity, not by water (docs/physics.md, "Wall friction"). A wall function gives the friction the
// water would feel at that distance instead, as finite-volume codes do on coarse meshes.
//
// Each fluid particle i within the kernel support 2h of a wall surface, at distance y from it with
// velocity v tangential to it, u = |v_t|, estimates the wall shear stress tau_w = rho u_tau^2 from
//   u / u_tau = y u_tau / nu                      (viscous sublayer, y+ = y u_tau / nu below 11.53)
//   u / u_tau = ln(E y u_tau / nu) / kappa        (log layer; kappa = 0.41, E = 9.793: a smooth wall)
// and feels the acceleration
//   a_i = -2 W1(y) u_tau^2 v_t / u,
// W1 the one-dimensional cubic spline with the run's h (support 2h, integral 1). The water beside a
// wall fills y > 0 with particles of volume V, so sum_i V_i 2 W1(y_i) is about 1 per unit of wall area
// and the force on the water is tau_w per unit area, spread over its first 2h. Near a corner each
// wall within 2h acts. y is held at dx/10 or more. The sums are per particle: the result does not
// depend on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sluice/core/particles.hpp"
#include "sluice/geometry/leaks.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

struct WallFrictionSettings {
  double kinematic_viscosity = 1e-6;  // nu = mu / rho0, m^2/s
  double h = 0.0;                     // smoothing length: the reach 2h and W1's width
  double dx = 0.0;                    // particle spacing: y >= dx/10
};

// The friction velocity u_tau of the law of the wall at distance y > 0 with speed u >= 0 there.
double friction_velocity(double u, double y, double nu);

struct WallFrictionResult {
  std::size_t felt = 0;           // fluid particles that felt a wall's friction
  double max_acceleration = 0.0;  // the largest |acceleration| among them, friction included
};

// Adds the wall friction to p.acceleration of the fluid particles within 2h of a wall. With `near`
// (its reach at least 2h), the particles in its clear cells are skipped; with `skip`, the particles i
// with skip[i] != 0 (another process's ghosts, whose accelerations nobody reads). The time step
// takes the result's max_acceleration into account: the friction can raise a particle's acceleration.
template <int Dim>
WallFrictionResult add_wall_friction(Particles<Dim>& p, const Solids<Dim>& solids,
                                     const WallFrictionSettings& settings, int threads,
                                     const SolidReach<Dim>* near = nullptr, const std::uint8_t* skip = nullptr);

}  // namespace sluice
