// The pair terms of the WCSPH equations (physics/pair_terms-inl.hpp) for one pair of doubles:
// sluice::pair::pressure and the others, for tests and scalar code.
#pragma once

#include "sluice/core/lane_math.hpp"

namespace sluice {
#include "sluice/physics/pair_terms-inl.hpp"
}  // namespace sluice
