// Geometry: polygons, wall filling, near-coincident removal, hydrostatic start, leak put-back.
#include <gtest/gtest.h>

#include <cmath>

#include "sluice/case/params.hpp"
#include "sluice/geometry/leaks.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/physics/eos.hpp"

using namespace sluice;

TEST(Polygon, ContainsAndClosestBoundaryPoint) {
  const Polygon box = Polygon::box({0.0, 0.0}, {2.0, 1.0});
  EXPECT_TRUE(box.contains({1.0, 0.5}));
  EXPECT_FALSE(box.contains({2.5, 0.5}));
  EXPECT_FALSE(box.contains({1.0, -0.1}));
  const Vec2 c = box.closest_boundary_point({1.9, 0.5});
  EXPECT_DOUBLE_EQ(c[0], 2.0);
  EXPECT_DOUBLE_EQ(c[1], 0.5);
  EXPECT_DOUBLE_EQ(box.area(), 2.0);
  const Polygon triangle{{{0.0, 0.0}, {4.0, 0.0}, {4.0, 2.0}}};  // a 1:2 slope
  EXPECT_TRUE(triangle.contains({3.0, 1.0}));
  EXPECT_FALSE(triangle.contains({1.0, 1.0}));
  EXPECT_NEAR(triangle.distance_to_boundary({2.0, 1.0}), 0.0, 1e-12);
}

TEST(Setup, DefaultTankHasThreeWallLayersAtDxSpacing) {
  const Case c = *load_builtin_case("dam_break");
  EXPECT_EQ(wall_layers(c), 3);  // 2h = 0.52 m at dx = 0.2 m
  const sluice::Setup s = build_setup(c);
  std::size_t walls = 0, fluid = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) (s.particles.is_fluid(i) ? fluid : walls)++;
  // Bottom and lid: 3 rows of 106 columns (x from -0.5 to 20.5); each side: 3 columns of 50 rows.
  EXPECT_EQ(walls, 2u * 3u * 106u + 2u * 3u * 50u);
  EXPECT_EQ(fluid, 100u * 10u + 15u * 15u);
  // The first wall layer is dx/2 behind each wall face, and every wall particle lies within 2h of it.
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (s.particles.is_fluid(i)) continue;
    const double x = s.particles.position[0][i], y = s.particles.position[1][i];
    const double depth = std::max({-x, x - c.tank_width, -y, y - c.tank_height});
    EXPECT_GT(depth, 0.0);
    EXPECT_LT(depth, 3 * c.dx);
    EXPECT_NEAR(std::fmod(depth + 1e-9, c.dx), 0.5 * c.dx, 1e-6);
  }
}

TEST(Setup, WaterOverlappingAnObstacleLeavesNoFluidOnAWallPoint) {
  Case c = *load_builtin_case("dam_break");
  c.walls.push_back(Region{"box", {5.0, 0.0}, {6.0, 1.0}, {}});
  const sluice::Setup s = build_setup(c);
  double closest = 1e9;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (!s.particles.is_fluid(i)) continue;
    const double x = s.particles.position[0][i], y = s.particles.position[1][i];
    EXPECT_FALSE(x > 5.0 && x < 6.0 && y < 1.0) << "fluid inside the obstacle at " << x << ", " << y;
    for (std::size_t j = 0; j < s.particles.size(); ++j)
      if (!s.particles.is_fluid(j))
        closest = std::min(closest, std::hypot(x - s.particles.position[0][j], y - s.particles.position[1][j]));
  }
  EXPECT_GE(closest, 0.5 * c.dx);
}

TEST(Setup, HydrostaticStartMatchesTheTaitEquationAtDepth) {
  const Case c = *load_builtin_case("dam_break");
  const sluice::Setup s = build_setup(c);
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const double x = s.particles.position[0][i], y = s.particles.position[1][i];
    if (!s.particles.is_fluid(i)) continue;
    const double surface = x < 3.0 ? 5.0 : 2.0;
    EXPECT_NEAR(eos.pressure(s.particles.density[i]), c.rest_density * 9.81 * (surface - y), 1e-6) << x << ", " << y;
  }
}

TEST(Leaks, AParticleInsideAWallIsPutBackWithItsNormalVelocityReversed) {
  Particles<2> p;
  p.add({0.5, -0.03}, Kind::fluid, 1000.0);  // 3 cm into the floor of a tank
  p.velocity[0][0] = 1.0;
  p.velocity[1][0] = -2.0;
  p.add({0.5, 0.5}, Kind::fluid, 1000.0);  // in the water: untouched
  const std::vector<Polygon> solids = {Polygon::box({-0.3, -0.3}, {2.3, 0.0})};
  const double dx = 0.1;
  EXPECT_EQ(put_back_leaked(p, solids, dx), 1u);
  EXPECT_NEAR(p.position[0][0], 0.5, 1e-12);
  EXPECT_NEAR(p.position[1][0], 0.5 * dx, 1e-12);  // half a spacing above the floor
  EXPECT_NEAR(p.velocity[0][0], 1.0, 1e-12);
  EXPECT_NEAR(p.velocity[1][0], 2.0, 1e-12);
  EXPECT_EQ(p.needs_density_repair[0], 1);
  EXPECT_EQ(p.needs_density_repair[1], 0);
  EXPECT_EQ(p.size(), 2u);  // never deleted
  EXPECT_EQ(put_back_leaked(p, solids, dx), 0u);
}

TEST(Setup, NearCoincidentPointsKeepOneOfEachPair) {
  Particles<2> p;
  p.add({0.0, 0.0}, Kind::wall, 1000.0);
  p.add({0.01, 0.0}, Kind::fluid, 1000.0);  // on the wall point: the fluid one goes
  p.add({1.0, 1.0}, Kind::fluid, 1000.0);
  p.add({1.0, 1.01}, Kind::fluid, 1000.0);  // fluid pair: one goes
  p.add({3.0, 3.0}, Kind::fluid, 1000.0);
  EXPECT_EQ(remove_near_coincident(p, 0.05), 2u);
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p.kind[0], Kind::wall);
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_EQ(p.id[i], i);
}
