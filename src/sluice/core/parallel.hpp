// When loops run on several threads. Light O(N) loops (reordering, per-particle terms, integration)
// only pay for a parallel region when there are enough particles: below this, the region's start and
// barrier cost more than the loop, badly so when the machine is busy with other work.
#pragma once

namespace sluice {

inline constexpr long light_loop_parallel_threshold = 20000;

}  // namespace sluice
