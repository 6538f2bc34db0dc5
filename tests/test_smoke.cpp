// The fast tier (label `smoke`, `make check`): every built-in case, 2D and 3D, at the resolution it
// ships with, set up and stepped a few times, with the invariants every step must keep: the particle
// count and the water's mass, every value finite, densities within the guard's bounds, no particle
// put back from inside a wall, time moving forward by the steps taken, and a restart from the state
// reached continuing it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

class BuiltinCase : public ::testing::TestWithParam<std::string> {};

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const auto& b : builtin_cases()) names.push_back(b.name);
  return names;
}

TEST_P(BuiltinCase, StepsKeepingItsInvariants) {
  const auto c = load_builtin_case(GetParam());
  ASSERT_TRUE(c.has_value());
  Simulation sim(*c, 2);
  const Diagnostics before = sim.diagnostics();
  ASSERT_TRUE(sim.check_health().ok());
  ASSERT_GT(before.fluid_particles, 0u);
  constexpr int steps = 5;
  double time = sim.time();
  for (int k = 0; k < steps; ++k) {
    sim.step(c->end_time);
    EXPECT_GT(sim.time(), time) << "step " << k;
    time = sim.time();
    const Health health = sim.check_health();
    ASSERT_TRUE(health.ok()) << health.offending << " bad particles after step " << k << ", the first: "
                             << (health.first.empty() ? "" : health.first[0].reason);
  }
  const Diagnostics after = sim.diagnostics();
  EXPECT_EQ(after.step, steps);
  EXPECT_TRUE(after.all_finite);
  EXPECT_EQ(after.leaks, 0);
  EXPECT_EQ(after.fluid_particles + static_cast<std::size_t>(after.outflow), before.fluid_particles);
  EXPECT_EQ(after.wall_particles, before.wall_particles);
  EXPECT_DOUBLE_EQ(after.total_mass + static_cast<double>(after.outflow) * sim.particle_mass(), before.total_mass);
  EXPECT_GT(after.min_density, 0.5 * c->rest_density);
  EXPECT_LT(after.max_density, 2.0 * c->rest_density);

  // The state reached, through a checkpoint, continues as the run does.
  Checkpoint cp = parse_checkpoint(checkpoint_bytes(sim, 0.0), GetParam() + ".bin");
  Simulation restarted(cp.config, std::move(cp.particles), cp.clock, 2);
  sim.step(c->end_time);
  restarted.step(c->end_time);
  EXPECT_EQ(restarted.time(), sim.time());
  EXPECT_EQ(restarted.diagnostics().kinetic_energy, sim.diagnostics().kinetic_energy);
}

INSTANTIATE_TEST_SUITE_P(Smoke, BuiltinCase, ::testing::ValuesIn(builtin_names()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
