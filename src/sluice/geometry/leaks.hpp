// Leak handling: a fluid particle found inside a solid wall is put back on the fluid side, half a
// particle spacing from the wall surface, with the normal component of its velocity reversed; its
// density is re-interpolated from its neighbours at the next force evaluation. Never deleted.
#pragma once

#include <cstddef>

#include "sluice/core/particles.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

// Returns the number of particles put back.
template <int Dim>
std::size_t put_back_leaked(Particles<Dim>& p, const Solids<Dim>& solids, double dx, int threads = 1);

// No penetration (physics.wall_no_penetration; the idea of DualSPHysics 5.4's mDBC penetration
// control, on the walls' geometry): before a drift, a fluid particle closer than dx/4 to a wall surface
// whose drift velocity u = v + tau a points into the wall (u.n < 0, n the surface's outward normal)
// loses the part f (u.n) n of its velocity, f = 1 - 4 d/dx clamped to [0, 2] at signed distance d:
// nothing at dx/4 (water at rest sits at dx/2), the approach stopped at the surface, reflected a
// quarter spacing inside. tau a is the acceleration the drift adds (the leapfrog's half kick; else
// none). Returns the number of particles changed.
template <int Dim>
std::size_t stop_wall_approach(Particles<Dim>& p, const Solids<Dim>& solids, double dx,
                               const typename Particles<Dim>::template Vector<double>* acceleration, double tau,
                               int threads = 1);

}  // namespace sluice
