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

}  // namespace sluice
