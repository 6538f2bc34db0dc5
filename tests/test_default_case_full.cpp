// The full default case (dx = 0.2 m, 30 s) with its invariants (mass exact, no leaks, energy bounded). Labelled "long".
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "sluice/case/params.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

TEST(DefaultCase, RunsStableToThirtySeconds) {
  const Case c = *load_builtin_case("dam_break");
  Simulation sim(c, 2);
  const auto start = std::chrono::steady_clock::now();
  while (sim.time() < c.end_time) {
    sim.step(c.end_time);
    const auto& p = sim.particles<2>();
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double speed = std::hypot(p.velocity[0][i], p.velocity[1][i]);
      ASSERT_TRUE(std::isfinite(p.position[0][i]) && std::isfinite(p.position[1][i]) && std::isfinite(speed));
      ASSERT_GT(p.density[i], 0.0);
      ASSERT_LE(p.density[i], 1.5 * c.rest_density);
      ASSERT_LT(speed, c.sound_speed);
      if (p.is_fluid(i)) {
        ASSERT_TRUE(p.position[0][i] >= 0 && p.position[0][i] <= c.tank_width) << "t = " << sim.time();
        ASSERT_TRUE(p.position[1][i] >= 0 && p.position[1][i] <= c.tank_height) << "t = " << sim.time();
      }
    }
  }
  const auto d = sim.diagnostics();
  std::cout << "steps " << d.step << ", leaks " << d.leaks << ", density " << d.min_density << ".." << d.max_density
            << ", wall " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
  EXPECT_EQ(d.leaks, 0);
}
