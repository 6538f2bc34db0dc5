// Body ids: which body a particle belongs to (Particles::body).
#pragma once

#include <cstdint>

namespace sluice {

// The body a particle belongs to (Particles::body): the water is body 0, the tank's own walls body 1,
// and the case's [[wall]] number k (from 0) body k + 2. A body is what moves as one (geometry/motion.hpp)
// and what the water's force is summed over.
namespace body_id {
inline constexpr std::uint8_t water = 0;
inline constexpr std::uint8_t tank = 1;
inline constexpr std::uint8_t first_wall = 2;
inline constexpr int most_walls = 255 - first_wall + 1;  // [[wall]] regions a case can have
}  // namespace body_id

}  // namespace sluice
