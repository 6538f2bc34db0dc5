// Leak handling: a fluid particle found inside a solid wall is put back on the fluid side, half a
// particle spacing from the wall surface, with the normal component of its velocity reversed; its
// density is re-interpolated from its neighbours at the next force evaluation. Never deleted.
#pragma once

#include <cstddef>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/geometry/polygon.hpp"

namespace sluice {

// Returns the number of particles put back.
std::size_t put_back_leaked(Particles<2>& p, const std::vector<Polygon>& solids, double dx, int threads = 1);

}  // namespace sluice
