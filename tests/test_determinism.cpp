// Results do not depend on the number of threads: the pair loop gathers per particle in a fixed order.
#include <gtest/gtest.h>

#include <string>

#include "sluice/case/params.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

// State in particle-id order.
std::vector<double> state_by_id(const Simulation& sim) {
  const auto& p = sim.particles<2>();
  std::vector<double> out(5 * p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t row = 5 * p.id[i];
    out[row + 0] = p.position[0][i];
    out[row + 1] = p.position[1][i];
    out[row + 2] = p.velocity[0][i];
    out[row + 3] = p.velocity[1][i];
    out[row + 4] = p.density[i];
  }
  return out;
}

}  // namespace

// Every wall treatment: with Adami and mDBC walls the wall densities come from sums over the fluid,
// each wall particle's by one thread.
class Determinism : public ::testing::TestWithParam<std::string> {};

TEST_P(Determinism, OneAndTwoThreadsGiveBitIdenticalResults) {
  const std::string walls = GetParam();
  for (const char* integrator : {"predictor_corrector", "euler", "leapfrog"}) {
    Case c = *load_builtin_case("dam_break");
    apply_override(c, "domain.dx=0.1");
    apply_override(c, std::string("time.integrator=") + integrator);
    apply_override(c, "physics.shepard_every=7");  // exercise the filter too
    // "mdbc+log_law": mDBC walls with the wall function (physics/wall_friction.hpp).
    const std::size_t plus = walls.find('+');
    apply_override(c, "physics.wall_boundary=" + walls.substr(0, plus));
    if (plus != std::string::npos) apply_override(c, "physics.wall_friction=" + walls.substr(plus + 1));
    // `switching` changes its thread count between steps, as a run on a busy machine does
    // (io/thread_governor.hpp); with the default integrator only, to keep the test short.
    const bool switches = std::string(integrator) == "leapfrog";
    Simulation one(c, 1), two(c, 2), switching(c, 2);
    ASSERT_GE(static_cast<long>(one.particles<2>().size()), parallel::pair_loop_threshold)
        << "too few particles for the neighbour loops to run on two threads";
    for (int s = 0; s < 150; ++s) {
      one.step();
      two.step();
      if (switches) {
        switching.set_threads(s % 5 < 2 ? 1 : 2);
        switching.step();
      }
    }
    EXPECT_EQ(one.time(), two.time()) << integrator << " " << walls;
    EXPECT_EQ(state_by_id(one), state_by_id(two)) << integrator << " " << walls;
    if (switches) {
      EXPECT_EQ(state_by_id(one), state_by_id(switching)) << integrator << " " << walls;
    }
    EXPECT_GT(one.diagnostics().max_speed, 0.5) << "the column must have started to move";
  }
}

INSTANTIATE_TEST_SUITE_P(WallBoundaries, Determinism, ::testing::Values("dynamic", "adami", "mdbc", "mdbc+log_law"));
