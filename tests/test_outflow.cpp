// Outflow: water that goes over the walls of an open tank and beyond their reach is removed and
// counted (Solver::remove_outflow), in the solver, in checkpoints and restarts, and in the run's
// diagnostics and summary.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <zlib.h>

#include "physics_cases.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

std::size_t fluid_count(const Particles<2>& p) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.size(); ++i) n += p.is_fluid(i);
  return n;
}

// Steps to `end`, the instability guard checked after every step as `sluice run` does.
void run_healthy(Simulation& sim, double end) {
  while (sim.time() < end) {
    sim.step(end);
    const Health health = sim.check_health();
    ASSERT_TRUE(health.ok()) << "t = " << sim.time() << ": " << health.first.front().reason;
  }
}

}  // namespace

TEST(Particles, EraseKeepsTheOthersInOrderWithEveryFieldInUse) {
  Particles<2> p;
  for (int i = 0; i < 5; ++i) p.add({0.1 * i, 1.0}, i == 4 ? Kind::wall : Kind::fluid, 1000.0 + i);
  p.resize(p.size());
  for (std::size_t i = 0; i < 5; ++i) {
    p.velocity[0][i] = static_cast<double>(i);
    p.position_start[1][i] = 10.0 + static_cast<double>(i);
    p.acceleration[0][i] = 20.0 + static_cast<double>(i);
  }
  p.acceleration_start[0].clear();  // a field not in use stays empty
  p.erase({0, 1, 0, 1, 0});
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p.id, (std::vector<std::uint32_t>{0, 2, 4}));
  EXPECT_EQ(p.density, (std::vector<double>{1000.0, 1002.0, 1004.0}));
  EXPECT_EQ(p.velocity[0], (std::vector<double>{0.0, 2.0, 4.0}));
  EXPECT_EQ(p.position_start[1], (std::vector<double>{10.0, 12.0, 14.0}));
  EXPECT_EQ(p.acceleration[0], (std::vector<double>{20.0, 22.0, 24.0}));
  EXPECT_EQ(p.kind.back(), Kind::wall);
  EXPECT_TRUE(p.acceleration_start[0].empty());
  EXPECT_EQ(p.acceleration_start[1].size(), 3u);
}

// Without outflow, the first particle over the wall stopped the run: the guard found it "far outside
// the tank". Now it leaves, counted, and what stays is all within the tank's reach.
TEST(Outflow, WaterThatGoesOverAnOpenTanksWallIsRemovedAndCounted) {
  const Case c = test_cases::spill_over_wall(0.005, false, 0.7);
  Simulation sim(c, 1);
  const Particles<2>& p = sim.particles<2>();
  const std::size_t fluid = fluid_count(p), walls = p.size() - fluid;
  // Nothing leaves before the water has reached the wall (its front does at 0.175 s), run up it and
  // gone over it (the first particles leave at 0.31 s, flying outward over the wall at 2.5 m/s). A jet
  // thrown up inside the tank (3.6 m/s up the wall at 0.24 s) is not outflow: it falls back.
  double first = -1.0;
  while (sim.time() < c.end_time) {
    sim.step(c.end_time);
    const Health health = sim.check_health();
    ASSERT_TRUE(health.ok()) << "t = " << sim.time() << ": " << health.first.front().reason;
    if (first < 0.0 && sim.clock().outflow > 0) first = sim.time();
  }
  const auto outflow = static_cast<std::size_t>(sim.clock().outflow);
  std::printf("[ outflow ] %zu of %zu fluid particles left the tank by t = %.2f s, the first at %.3f s\n", outflow,
              fluid, sim.time(), first);
  EXPECT_GT(first, 0.2);
  EXPECT_GT(outflow, fluid / 20);
  EXPECT_EQ(fluid_count(p) + outflow, fluid);
  EXPECT_EQ(p.size() - fluid_count(p), walls);
  const Diagnostics d = sim.diagnostics();
  EXPECT_EQ(d.outflow, sim.clock().outflow);
  EXPECT_EQ(d.fluid_particles + outflow, fluid);
  sim.visit([&](const auto& solver) {
    for (std::size_t i = 0; i < p.size(); ++i) EXPECT_TRUE(solver.in_reach(i, solver.reach()) && solver.within_walls(i, solver.reach())) << "particle " << p.id[i];
  });

  // A frame holds the particles that remain, in increasing id order (the ids of those gone missing),
  // and reads back as written.
  const Frame frame = frame_from_npz(frame_to_npz(make_frame(sim)), "after outflow");
  ASSERT_EQ(frame.size(), p.size());
  const auto& ids = frame.values<std::uint32_t>("id");
  const auto& x = frame.values<double>("x");
  for (std::size_t k = 1; k < ids.size(); ++k) ASSERT_LT(ids[k - 1], ids[k]);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const auto k = static_cast<std::size_t>(std::lower_bound(ids.begin(), ids.end(), p.id[i]) - ids.begin());
    ASSERT_EQ(ids[k], p.id[i]);
    EXPECT_EQ(x[2 * k], p.position[0][i]);
    EXPECT_EQ(x[2 * k + 1], p.position[1][i]);
  }
}

TEST(Outflow, AClosedTankKeepsItsWater) {
  const Case c = test_cases::spill_over_wall(0.005, true, 0.7);
  Simulation sim(c, 1);
  const std::size_t n = sim.particle_count();
  run_healthy(sim, c.end_time);
  EXPECT_EQ(sim.clock().outflow, 0);
  EXPECT_EQ(sim.particle_count(), n);
}

// A checkpoint written after water has left holds the count; the restart continues bit for bit as
// the run that never stopped (with either integrator: the leapfrog's carried rates are compacted with
// the particles). A checkpoint whose ids do not fit its count is refused.
class OutflowRestart : public ::testing::TestWithParam<const char*> {};

TEST_P(OutflowRestart, ContinuesExactly) {
  Case c = test_cases::spill_over_wall(0.005, false, 0.6);
  c.integrator = GetParam() == std::string("leapfrog") ? Integrator::leapfrog : Integrator::predictor_corrector;
  Simulation straight(c, 1);
  run_healthy(straight, 0.45);
  ASSERT_GT(straight.clock().outflow, 0);
  const std::string bytes = checkpoint_bytes(straight, 1.0);
  const std::int64_t straight_outflow = straight.clock().outflow;
  Checkpoint cp = parse_checkpoint(bytes, "outflow.bin");
  EXPECT_EQ(cp.clock.outflow, straight.clock().outflow);
  Simulation restarted(cp.config, std::move(cp.particles), cp.clock, 1);
  run_healthy(straight, 0.6);
  run_healthy(restarted, 0.6);
  EXPECT_EQ(restarted.clock().outflow, straight.clock().outflow);
  EXPECT_EQ(restarted.clock().step, straight.clock().step);
  const Particles<2>& a = straight.particles<2>();
  const Particles<2>& b = restarted.particles<2>();
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.position[0], b.position[0]);
  EXPECT_EQ(a.position[1], b.position[1]);
  EXPECT_EQ(a.density, b.density);

  // The same file claiming no outflow: its ids run past its particle count.
  std::string lying = bytes;
  // After the signature, version, dimension, case (its length, its text), the five clock fields, the
  // rates-carried byte and, when 1, the four rates (io/checkpoint.hpp).
  std::uint64_t case_length = 0;
  std::memcpy(&case_length, lying.data() + 16, 8);
  const std::size_t at = 24 + case_length + 5 * 8 + 1 + (lying[24 + case_length + 40] == 1 ? 4 * 8 : 0);
  std::int64_t stored = 0;
  std::memcpy(&stored, lying.data() + at, 8);
  ASSERT_EQ(stored, straight_outflow);
  std::memset(lying.data() + at, 0, 8);
  const auto crc = static_cast<std::uint32_t>(
      crc32(0L, reinterpret_cast<const Bytef*>(lying.data()), static_cast<uInt>(lying.size() - 4)));
  std::memcpy(lying.data() + lying.size() - 4, &crc, 4);
  try {
    parse_checkpoint(lying, "lying.bin");
    ADD_FAILURE() << "a checkpoint whose ids do not fit its count was read";
  } catch (const CaseError& e) {  // the file reads; a value in it is refused (exit status 2)
    EXPECT_NE(std::string(e.what()).find("lying.bin: not a usable checkpoint: particle ids are not a permutation"),
              std::string::npos)
        << e.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Integrators, OutflowRestart, ::testing::Values("predictor_corrector", "leapfrog"));
