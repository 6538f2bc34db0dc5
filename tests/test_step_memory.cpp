// The steps reuse the memory they free (core/heap.hpp): after the first steps, a step faults in no
// new pages. Each test runs in a process of its own (ctest), whose allocator has seen nothing else.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/simulation.hpp"

namespace {

long minor_faults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

}  // namespace

// SPHERIC test 2 at 103k particles on two threads: a step's temporaries (the pair loops' fluid
// counts, mDBC's compact fluid arrays, arrays of one value a particle) were given back to the system
// after every step, the second thread's from its own heap, and faulted in again at the next: 589
// page faults a step with the allocator's defaults.
TEST(StepMemory, StepsFaultInNoNewPages) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer's allocator holds freed memory back in quarantine: new pages every step";
#endif
  sluice::Case c = *sluice::load_builtin_case("spheric2");
  sluice::apply_override(c, "domain.dx=0.025");
  sluice::Simulation sim(c, 2);
  for (int i = 0; i < 3; ++i) sim.step();
  const long before = minor_faults();
  constexpr int steps = 10;
  for (int i = 0; i < steps; ++i) sim.step();
  const double per_step = static_cast<double>(minor_faults() - before) / steps;
  EXPECT_LT(per_step, 5.0) << sim.particle_count() << " particles";
}
