// How OpenMP threads wait between the parallel loops of a step. Threads that sleep at once (the
// passive policy) cost a wake-up, a system call and a context switch at each of the dozen loops of a
// step: on a quiet machine, 12 % of a two-thread run's samples at 24k particles were in the kernel's
// futex calls. Threads that spin for long (libgomp's default is 300,000 checks) take the core another
// process needs: with a busy process beside, a two-thread run spinning 20,000 checks took 2.8 times
// as long as with the passive policy. So the threads spin briefly, long enough for the gaps between the loops
// of one step, and then sleep; and a run on a busy machine steps with fewer threads
// (io/thread_governor.hpp).
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <string_view>

namespace sluice {

inline constexpr const char* kThreadSpinCount = "10000";  // GOMP_SPINCOUNT

// The OpenMP runtime reads its settings once, before main(), so unless the user chose them the
// program restarts itself once with these (a program's first call). Not under valgrind (which
// preloads its vgpreload libraries): there /proc/self/exe is the valgrind tool, which refuses to be
// started directly, and the restart would leave the profiler.
inline void restart_with_brief_spinning(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  const char* preload = std::getenv("LD_PRELOAD");
  if (preload != nullptr && std::string_view(preload).find("vgpreload") != std::string_view::npos) return;
  if (::setenv("OMP_WAIT_POLICY", "PASSIVE", 1) == 0 && ::setenv("GOMP_SPINCOUNT", kThreadSpinCount, 1) == 0)
    ::execv("/proc/self/exe", argv);  // returns only if it failed; then carry on as we are
}

}  // namespace sluice
