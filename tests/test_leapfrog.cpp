// The leapfrog integrator (time.integrator = "leapfrog", integrate/integrators.hpp): its update on a
// harmonic oscillator (second order, energy bounded where the predictor-corrector's grows), one force
// evaluation per step through the solver, bit-identical results on 1 and 2 threads, exact restarts
// from a checkpoint (with the carried rates, and after a leak cleared them), and the instability
// guard's way back to the start of a step. (Still water with the leapfrog, 2D and 3D: test_physics.cpp.)
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "physics_cases.hpp"
#include "sluice/case/params.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/integrate/integrators.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

// One fluid particle on a spring, x'' = -w^2 x, moved by the integrators' updates with the force
// "evaluated" by hand where the solver would call evaluate().
struct Oscillator {
  double omega = 2.0 * std::numbers::pi;  // period 1 s
  Particles<2> p;

  Oscillator() {
    p.add({1.0, 0.0}, Kind::fluid, 1000.0);
    p.resize(1);
  }
  void evaluate() {
    for (int d = 0; d < 2; ++d) p.acceleration[d][0] = -omega * omega * p.position[d][0];
    p.density_rate[0] = 0.0;
  }
  [[nodiscard]] double energy() const {  // per unit mass
    double e = 0.0;
    for (int d = 0; d < 2; ++d)
      e += 0.5 * p.velocity[d][0] * p.velocity[d][0] + 0.5 * omega * omega * p.position[d][0] * p.position[d][0];
    return e;
  }

  // The leapfrog as Solver::leapfrog_step drives it (the rates carried from the previous step); the
  // first step evaluates first. Calls after_step() after each step.
  template <class F>
  void leapfrog(double dt, int steps, F after_step) {
    evaluate();
    for (int s = 0; s < steps; ++s) {
      std::swap(p.acceleration, p.acceleration_start);
      std::swap(p.density_rate, p.density_rate_start);
      leapfrog_kick_drift(p, dt, 1000.0, 1);
      evaluate();
      leapfrog_final_kick(p, dt, 1000.0, 1);
      after_step();
    }
  }
  // The predictor-corrector as Solver::step drives it.
  void predictor_corrector(double dt, int steps) {
    for (int s = 0; s < steps; ++s) {
      evaluate();
      predictor_update(p, dt, 1000.0, 1);
      evaluate();
      corrector_update(p, dt, 1000.0, 1);
    }
  }
};

// State in particle-id order.
template <int Dim>
std::vector<double> state_by_id(const Simulation& sim) {
  const auto& p = sim.particles<Dim>();
  constexpr int row_size = 2 * Dim + 1;
  std::vector<double> out(row_size * p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t row = row_size * p.id[i];
    for (int d = 0; d < Dim; ++d) {
      out[row + d] = p.position[d][i];
      out[row + Dim + d] = p.velocity[d][i];
    }
    out[row + 2 * Dim] = p.density[i];
  }
  return out;
}

Case coarse_dam_break(const std::string& integrator) {
  Case c = *load_builtin_case("dam_break");
  apply_override(c, "domain.dx=0.1");
  apply_override(c, "time.integrator=" + integrator);
  return c;
}

}  // namespace

// Over 100 periods at 100 steps a period the leapfrog's energy stays within 0.1 % (it oscillates by
// about (w dt)^2 / 4 and does not drift), while the predictor-corrector's grows by its amplification
// 1 + (w dt)^4 / 4 per step: 4 %. The position error is second order in dt.
TEST(LeapfrogUpdate, HarmonicOscillatorKeepsItsEnergyAndIsSecondOrder) {
  const double dt = 0.01;
  const int steps = 10000;  // 100 periods
  Oscillator lf;
  lf.p.velocity[1][0] = lf.omega;  // a circular orbit: x = cos(wt), y = sin(wt)
  const double e0 = lf.energy();
  double worst = 0.0;
  lf.leapfrog(dt, steps, [&] { worst = std::max(worst, std::abs(lf.energy() / e0 - 1.0)); });
  Oscillator pc;
  pc.p.velocity[1][0] = pc.omega;
  pc.predictor_corrector(dt, steps);
  const double pc_drift = pc.energy() / e0 - 1.0;
  std::printf("100 periods at w dt = %.4f: leapfrog energy within %.2e, predictor-corrector energy %+.2e\n",
              lf.omega * dt, worst, pc_drift);
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(pc_drift, 0.02);

  // Position error after one period against cos(w t), at dt and dt/2: the ratio is 4 for second order.
  auto error_after_one_period = [](int n) {
    Oscillator o;
    o.p.velocity[1][0] = o.omega;
    o.leapfrog(1.0 / n, n, [] {});
    return std::hypot(o.p.position[0][0] - 1.0, o.p.position[1][0]);
  };
  const double coarse = error_after_one_period(50), fine = error_after_one_period(100);
  std::printf("error after one period: %.3e at 50 steps, %.3e at 100 (ratio %.2f)\n", coarse, fine, coarse / fine);
  EXPECT_GT(coarse / fine, 3.6);
  EXPECT_LT(coarse / fine, 4.4);
}

// What an evaluation does to the state it evaluated carries into the step's end: the final kick adds
// dt/2 (D(n+1) - D(n)) to the density the evaluation left (the Shepard filter's, a wall's), and a wall
// density stays at or above the floor.
TEST(LeapfrogUpdate, TheFinalKickKeepsWhatTheEvaluationWroteAndWallsKeepTheirFloor) {
  Particles<2> p;
  p.add({0.0, 0.0}, Kind::fluid, 1000.0);
  p.add({1.0, 0.0}, Kind::wall, 1000.0);
  p.resize(2);
  const double dt = 0.1;
  p.density_rate_start = {20.0, -50.0};
  p.acceleration_start[1] = {-10.0, 0.0};
  leapfrog_kick_drift(p, dt, 1000.0, 1);
  EXPECT_DOUBLE_EQ(p.density[0], 1002.0);         // rho* = rho + dt D(n)
  EXPECT_EQ(p.density[1], 1000.0);                // floored
  EXPECT_DOUBLE_EQ(p.position[1][0], -0.05);      // x + dt (v + dt/2 a)
  EXPECT_DOUBLE_EQ(p.velocity[1][0], -1.0);       // v* = v + dt a
  EXPECT_EQ(p.position_start[1][0], 0.0);         // y(n) kept for the guard
  EXPECT_EQ(p.density_start[0], 1000.0);
  p.density[0] = 1001.0;  // as a Shepard filter would rewrite rho*
  p.density_rate = {40.0, -50.0};
  p.acceleration[1] = {-12.0, 0.0};
  leapfrog_final_kick(p, dt, 1000.0, 1);
  EXPECT_DOUBLE_EQ(p.density[0], 1002.0);         // 1001 + dt/2 (40 - 20)
  EXPECT_EQ(p.density[1], 1000.0);
  EXPECT_DOUBLE_EQ(p.velocity[1][0], -1.1);       // v(n) + dt/2 (a(n) + a(n+1))
  EXPECT_EQ(p.position[1][0], -0.05);             // the final kick does not move
}

// One force evaluation per step (and one more at the first step, which has no carried rates), against
// the predictor-corrector's two; the wall time of each over the same simulated time is printed (not
// asserted: the machine is shared).
TEST(Leapfrog, EvaluatesTheForcesOncePerStep) {
  auto run = [](const std::string& integrator, int steps, double* seconds) {
    Simulation sim(test_cases::hydrostatic_tank(1.0, 0.5, 0.025, integrator, 0.2), 1);
    const auto start = std::chrono::steady_clock::now();
    for (int s = 0; s < steps; ++s) sim.step();
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return sim.force_evaluations();
  };
  double leapfrog_seconds = 0.0, pc_seconds = 0.0;
  EXPECT_EQ(run("leapfrog", 300, &leapfrog_seconds), 301);
  EXPECT_EQ(run("predictor_corrector", 300, &pc_seconds), 600);
  std::printf("300 steps of still water: leapfrog %.3f s, predictor-corrector %.3f s (ratio %.2f)\n", leapfrog_seconds,
              pc_seconds, leapfrog_seconds / pc_seconds);
}

// The project's guarantee: 1 and 2 threads give the same bits. test_determinism.cpp checks the
// leapfrog with dynamic and Adami walls; here mDBC walls (their velocities and densities written at
// each evaluation) with particle shifting and the Shepard filter.
TEST(Leapfrog, OneAndTwoThreadsGiveBitIdenticalResultsWithMdbcWallsAndShifting) {
  Case c = coarse_dam_break("leapfrog");
  apply_override(c, "physics.shepard_every=7");
  apply_override(c, "physics.wall_boundary=mdbc");
  apply_override(c, "physics.shifting=2");
  Simulation one(c, 1), two(c, 2);
  ASSERT_GE(static_cast<long>(one.particles<2>().size()), parallel::pair_loop_threshold)
      << "too few particles for the neighbour loops to run on two threads";
  for (int s = 0; s < 150; ++s) {
    one.step();
    two.step();
  }
  EXPECT_EQ(one.time(), two.time());
  EXPECT_EQ(state_by_id<2>(one), state_by_id<2>(two));
  EXPECT_GT(one.diagnostics().max_speed, 0.5) << "the column must have started to move";
}

// A restart from a checkpoint continues bit for bit: the carried rates and their summary are in it.
TEST(Leapfrog, ARestartFromACheckpointContinuesBitForBit) {
  Case c = coarse_dam_break("leapfrog");
  apply_override(c, "physics.shepard_every=7");
  Simulation sim(c, 1);
  for (int s = 0; s < 40; ++s) sim.step();
  ASSERT_TRUE(sim.clock().rates_carried);
  Checkpoint cp = parse_checkpoint(checkpoint_bytes(sim, 1.0), "leapfrog.bin");
  EXPECT_TRUE(cp.clock.rates_carried);
  EXPECT_EQ(cp.clock.rates.max_acceleration, sim.clock().rates.max_acceleration);
  EXPECT_EQ(cp.clock.rates.max_relative_speed, sim.clock().rates.max_relative_speed);
  EXPECT_EQ(std::get<Particles<2>>(cp.particles).acceleration[1], sim.particles<2>().acceleration[1]);
  EXPECT_EQ(std::get<Particles<2>>(cp.particles).density_rate, sim.particles<2>().density_rate);
  Simulation resumed(cp.config, std::move(cp.particles), cp.clock, 1);
  for (int s = 0; s < 60; ++s) {
    sim.step();
    resumed.step();
  }
  EXPECT_EQ(resumed.force_evaluations(), 60);  // no evaluation at the restart: the rates came with it
  EXPECT_EQ(resumed.time(), sim.time());
  EXPECT_EQ(resumed.particles<2>().id, sim.particles<2>().id);
  EXPECT_EQ(state_by_id<2>(resumed), state_by_id<2>(sim));
}

// A particle put back from inside a wall clears the carried rates: the next step evaluates at the
// state it starts from first (two evaluations), and a checkpoint written in between (without rates,
// with the pending density repair) continues bit for bit too.
TEST(Leapfrog, ALeakClearsTheCarriedRatesAndARestartThenStillContinuesBitForBit) {
  Case c = coarse_dam_break("leapfrog");
  Simulation sim(c, 1);
  for (int s = 0; s < 10; ++s) sim.step();
  Checkpoint cp = parse_checkpoint(checkpoint_bytes(sim, 1.0), "leapfrog.bin");
  auto& p = std::get<Particles<2>>(cp.particles);
  // A fluid particle on the floor, pushed into it and moving down (the floor's surface is y = 0).
  std::size_t low = p.size();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.is_fluid(i) && (low == p.size() || p.position[1][i] < p.position[1][low])) low = i;
  ASSERT_LT(low, p.size());
  p.position[1][low] = -0.3 * c.dx;
  p.velocity[1][low] = -1.0;
  Simulation leaky(cp.config, std::move(cp.particles), cp.clock, 1);
  leaky.step();
  ASSERT_EQ(leaky.clock().leaks, 1);
  EXPECT_FALSE(leaky.clock().rates_carried);
  EXPECT_EQ(leaky.force_evaluations(), 1);
  Checkpoint after = parse_checkpoint(checkpoint_bytes(leaky, 1.0), "after_leak.bin");
  EXPECT_FALSE(after.clock.rates_carried);
  Simulation resumed(after.config, std::move(after.particles), after.clock, 1);
  leaky.step();
  EXPECT_EQ(leaky.force_evaluations(), 3);  // the step after the leak evaluates twice
  EXPECT_TRUE(leaky.clock().rates_carried);
  for (int s = 0; s < 30; ++s) leaky.step();
  for (int s = 0; s < 31; ++s) resumed.step();
  EXPECT_EQ(resumed.time(), leaky.time());
  EXPECT_EQ(state_by_id<2>(resumed), state_by_id<2>(leaky));
}

// The instability guard's restore_saved_state() goes back to the state and the carried rates at the
// start of the step, so the checkpoint it then writes continues exactly as the step did.
TEST(Leapfrog, RestoreSavedStateGoesBackToTheStartOfTheStepWithItsRates) {
  Case c = coarse_dam_break("leapfrog");
  apply_override(c, "physics.shepard_every=7");
  Simulation sim(c, 1);
  for (int s = 0; s < 21; ++s) sim.step();
  const std::vector<double> before = state_by_id<2>(sim);
  const Clock clock_before = sim.clock();
  sim.step();  // from step 21: the Shepard filter is due at its evaluation
  const std::vector<double> after_one = state_by_id<2>(sim);
  sim.restore_saved_state();
  EXPECT_EQ(state_by_id<2>(sim), before);
  EXPECT_EQ(sim.clock().step, clock_before.step);
  EXPECT_EQ(sim.clock().time, clock_before.time);
  EXPECT_TRUE(sim.clock().rates_carried);
  Checkpoint cp = parse_checkpoint(checkpoint_bytes(sim, 1.0), "restored.bin");
  Simulation again(cp.config, std::move(cp.particles), cp.clock, 1);
  again.step();
  EXPECT_EQ(state_by_id<2>(again), after_one);
}
