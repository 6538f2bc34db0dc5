// Floating bodies in water (solver/bodies.hpp, geometry/floating_body.hpp): the water's force on a
// body is the reaction of what its particles give the water, so momentum is conserved; runs on one
// and two threads and restarts give the same bits; bodies meet the floor and each other by contact;
// a body that starts outside the tank or in another wall is refused; bodies/<name>.csv holds the
// motion. (The floating box's draft is tested through `sluice validate --quick --case floating_box`,
// tests/test_validation.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/load.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/run.hpp"
#include "sluice/simulation.hpp"

namespace sluice {
namespace {

Case builtin(const std::string& name, const std::vector<std::string>& overrides) {
  Case c = *load_builtin_case(name);
  apply_overrides(c, overrides);
  return c;
}

// The floating body's state (the first floating wall's) of a 2D run.
FloatingState floater(const Simulation& sim) {
  FloatingState s;
  sim.visit([&](const auto& solver) {
    for (const auto& body : solver.bodies().list())
      if (body.floats) s = body.floating.state();
  });
  return s;
}

double body_mass(const Simulation& sim) {
  double m = 0.0;
  sim.visit([&](const auto& solver) {
    for (const auto& body : solver.bodies().list())
      if (body.floats) m = body.floating.model().mass;
  });
  return m;
}

// Without gravity, a blob of water under pressure bursts against a floating box in the middle of a
// large tank (the tank's walls out of the water's reach): what the water loses in momentum the box
// gains, the total staying zero to round-off, with each integrator.
TEST(FloatingBodies, TheWaterAndABodyConserveMomentum) {
  for (const char* integrator : {"predictor_corrector", "leapfrog", "euler"}) {
    SCOPED_TRACE(integrator);
    const Case c = parse_case(fmt::format(R"(
[domain]
dx = 0.02
[tank]
width = 2.0
height = 2.0
[fluid]
sound_speed = 20.0
[physics]
gravity = [0.0, 0.0]
initial_pressure = 2000.0
wall_friction = "none"
wall_no_penetration = false
[time]
end = 0.05
integrator = "{}"
[[water]]
min = [0.6, 0.7]
max = [1.0, 1.3]
[[wall]]
name = "box"
min = [1.01, 0.85]
max = [1.21, 1.15]
[wall.floating]
density = 400.0
)",
                                          integrator),
                              "burst.toml");
    Simulation sim(c, 1);
    while (sim.time() < c.end_time) sim.step(c.end_time);
    const auto& p = sim.particles<2>();
    const double m = c.rest_density * c.dx * c.dx;
    std::array<double, 2> water{}, scale{};
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!p.is_fluid(i)) continue;
      for (int d = 0; d < 2; ++d) {
        water[d] += m * p.velocity[d][i];
        scale[d] += m * std::abs(p.velocity[d][i]);
      }
    }
    const FloatingState s = floater(sim);
    const double M = body_mass(sim);
    EXPECT_EQ(sim.clock().leaks, 0);
    EXPECT_GT(sim.clock().step, 100);
    // The box was pushed (the test sees the coupling at work) ...
    EXPECT_GT(M * s.velocity[0], 0.05 * scale[0]);
    // ... and the water's momentum is its opposite, to round-off.
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(water[d] + M * s.velocity[d], 0.0, 1e-12 * scale[d]) << d;
  }
}

// One and two threads, and a restart from a checkpoint taken mid-run, give the same bits: the
// particles and the body's state (the leapfrog's carried accelerations are in the checkpoint).
TEST(FloatingBodies, ThreadsAndRestartsGiveTheSameBits) {
  for (const char* integrator : {"predictor_corrector", "leapfrog"}) {
    SCOPED_TRACE(integrator);
    const Case c = builtin("floating_box", {"domain.dx=0.02", "time.end=0.1", std::string("time.integrator=") + integrator});
    Simulation one(c, 1), two(c, 2);
    while (one.time() < 0.05) one.step(0.05);
    const std::string saved = checkpoint_bytes(one, 1.0);
    while (one.time() < c.end_time) one.step(c.end_time);
    while (two.time() < 0.05) two.step(0.05);
    while (two.time() < c.end_time) two.step(c.end_time);
    Checkpoint cp = parse_checkpoint(saved, "float.bin");
    Simulation again(cp.config, std::move(cp.particles), cp.clock, 1);
    while (again.time() < c.end_time) again.step(c.end_time);
    const auto state = [](const Simulation& sim) {
      const auto& p = sim.particles<2>();
      std::vector<std::array<double, 5>> by_id(p.size());
      for (std::size_t i = 0; i < p.size(); ++i)
        by_id[p.id[i]] = {p.position[0][i], p.position[1][i], p.velocity[0][i], p.velocity[1][i], p.density[i]};
      return by_id;
    };
    const auto expected = state(one);
    EXPECT_NE(floater(one).centre[1], 0.55);  // it moved
    for (const Simulation* other : {&two, &again}) {
      ASSERT_EQ(other->clock().step, one.clock().step);
      EXPECT_EQ(state(*other), expected) << (other == &two ? "two threads" : "restarted");
      EXPECT_EQ(other->clock().floating, one.clock().floating) << (other == &two ? "two threads" : "restarted");
    }
  }
}

// The bodies of `sim` that float: their states and masses, in body order.
std::vector<std::pair<FloatingState, FloatingModel>> floaters(const Simulation& sim) {
  std::vector<std::pair<FloatingState, FloatingModel>> v;
  sim.visit([&](const auto& solver) {
    for (const auto& body : solver.bodies().list())
      if (body.floats) v.emplace_back(body.floating.state(), body.floating.model());
  });
  return v;
}

// A nearly dry tank (a puddle in the far corner) for bodies to meet its walls and each other.
std::string dry_tank(const std::string& gravity, const std::string& walls) {
  return R"(
[domain]
dx = 0.02
[tank]
width = 2.0
height = 1.0
[fluid]
sound_speed = 20.0
[physics]
gravity = )" + gravity + R"(
[time]
end = 0.8
[[water]]
min = [0.0, 0.0]
max = [0.1, 0.04]
)" + walls;
}

// Contact: a box dropped onto the tank's floor from 0.3 m lands without passing into it and rests
// on it, its bottom within a hundredth of a spacing of the floor, the contacts carrying its weight.
// Without contact it falls through the floor and the run stops.
TEST(FloatingBodies, ABoxDroppedOnTheFloorRestsOnIt) {
  const Case c = parse_case(dry_tank("[0.0, -9.81]", R"(
[[wall]]
name = "box"
min = [1.4, 0.3]
max = [1.8, 0.5]
[wall.floating]
density = 500.0
friction = 0.3
)"),
                            "drop.toml");
  Simulation sim(c, 2);
  double lowest = 1.0;
  while (sim.time() < c.end_time) {
    sim.step(c.end_time);
    lowest = std::min(lowest, floaters(sim)[0].first.centre[1] - 0.1);
    ASSERT_TRUE(sim.check_health().ok()) << sim.check_health().wall_outside;
  }
  const auto [s, m] = floaters(sim)[0];
  EXPECT_NEAR(s.centre[1] - 0.1, 0.0, 0.01 * c.dx);
  EXPECT_GT(lowest, -0.25 * c.dx);  // the landing at 2.4 m/s presses in by less than a quarter spacing
  EXPECT_NEAR(s.contact_force[1], m.mass * 9.81, 0.01 * m.mass * 9.81);
  EXPECT_NEAR(s.velocity[1], 0.0, 1e-3);
}

// Two floating boxes meet off-centre without water or gravity: linear momentum is kept to round-off
// and angular momentum to the integrator's error (each body receives the reaction of the forces it
// exerts, at the same point), they part more slowly than they met
// (the contact's damping), and both turn.
TEST(FloatingBodies, TwoBodiesCollideKeepingMomentum) {
  const Case c = parse_case(dry_tank("[0.0, 0.0]", R"(
[[wall]]
name = "a"
min = [0.6, 0.4]
max = [0.8, 0.6]
[wall.floating]
density = 500.0
velocity = [1.0, 0.0]
[[wall]]
name = "b"
min = [1.0, 0.45]
max = [1.3, 0.65]
[wall.floating]
density = 800.0
)"),
                            "collide.toml");
  Simulation sim(c, 1);
  const auto momenta = [](const Simulation& s) {
    std::array<double, 3> p{};  // x, y, and about the origin
    for (const auto& [st, m] : floaters(s)) {
      p[0] += m.mass * st.velocity[0];
      p[1] += m.mass * st.velocity[1];
      p[2] += m.inertia[2] * st.omega[2] + m.mass * (st.centre[0] * st.velocity[1] - st.centre[1] * st.velocity[0]);
    }
    return p;
  };
  const auto before = momenta(sim);
  while (sim.time() < 0.5) sim.step(0.5);
  const auto after = momenta(sim);
  // Linear momentum to round-off; angular momentum to the integrator's error (the moment arms move
  // within a step): 6e-9 of it measured.
  EXPECT_NEAR(after[0], before[0], 1e-12 * std::abs(before[0]));
  EXPECT_NEAR(after[1], before[1], 1e-12 * std::abs(before[0]));
  EXPECT_NEAR(after[2], before[2], 1e-7 * std::abs(before[2]));
  const auto f = floaters(sim);
  const double parting = f[1].first.velocity[0] - f[0].first.velocity[0];
  EXPECT_GT(parting, 0.05);
  EXPECT_LT(parting, 1.0);
  EXPECT_GT(std::abs(f[0].first.omega[2]), 0.1);
  EXPECT_GT(std::abs(f[1].first.omega[2]), 0.1);
}

TEST(FloatingBodies, ABodyOutsideTheTankOrInAnotherWallAtTheStartIsRefused) {
  const auto refusal = [](const Case& c) {
    try {
      Simulation sim(c, 1);
    } catch (const CaseError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string out = refusal(builtin("floating_box", {"domain.dx=0.02", "wall[0].min=[-0.1, 0.45]"}));
  EXPECT_NE(out.find("wall 1 (box) leaves the tank through the wall at the low end of x at the start"),
            std::string::npos)
      << out;
  Case two = builtin("floating_box", {"domain.dx=0.02"});
  Region post;
  post.name = "post";
  post.min = {1.1, 0.0, 0.0};
  post.max = {1.2, 0.6, 0.0};
  two.walls.push_back(post);
  const std::string overlap = refusal(two);
  EXPECT_NE(overlap.find("overlap at the start"), std::string::npos) << overlap;
}

// bodies/box.csv: the floating body's header, and rows whose last one is the body's state at the end.
TEST(FloatingBodies, ItsSeriesHoldsTheMotionAndTheLoads) {
  const Case c = builtin("floating_box", {"domain.dx=0.02", "time.end=0.2", "output.interval=0.1"});
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "sluice_floating_series";
  std::filesystem::remove_all(dir);
  RunOptions options;
  options.output_dir = dir;
  options.progress = RunOptions::Progress::none;
  std::ostringstream log;
  run_case(c, options, log);
  std::ifstream in(dir / "bodies" / "box.csv");
  std::string header, line, last;
  std::getline(in, header);
  EXPECT_EQ(header,
            "time,x,y,angle,vx,vy,angular_velocity,fx,fy,moment,spring_fx,spring_fy,spring_moment,damper_fx,"
            "damper_fy,damper_moment,contact_fx,contact_fy,contact_moment");
  int rows = 0;
  while (std::getline(in, line)) last = line, ++rows;
  EXPECT_GT(rows, 100);
  std::vector<double> v;
  std::stringstream fields(last);
  for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
  ASSERT_EQ(v.size(), 19u);
  EXPECT_DOUBLE_EQ(v[0], 0.2);
  EXPECT_LT(v[2], 0.55);  // it has fallen into the water
  EXPECT_GT(v[8], 100.0);  // buoyed
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sluice
