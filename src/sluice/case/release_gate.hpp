// The gate of release.gate: the first water region held behind a plate lifted at a constant speed,
// as laboratories release a dam break, made a moving [[wall]] of the case.
#pragma once

#include "sluice/case/case.hpp"

namespace sluice {

// The case with its release gate as a [[wall]] named "gate" (after the case's own walls) and
// release.gate false, so that a case expanded once is not expanded again (a checkpoint stores the
// expanded case); the case as it is without release.gate. Throws CaseError if the first water region
// is missing or not a box, or the case has a wall named "gate" already.
[[nodiscard]] Case with_release_gate(const Case& c);

}  // namespace sluice
