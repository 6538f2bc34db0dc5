// Geometry: polygons, wall filling, near-coincident removal, hydrostatic start, leak put-back, the
// ghost nodes of the mDBC walls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

#include "sluice/case/case_error.hpp"
#include "sluice/case/params.hpp"
#include "sluice/geometry/box.hpp"
#include "sluice/geometry/leaks.hpp"
#include "sluice/geometry/polygon.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/geometry/tank_walls.hpp"
#include "sluice/geometry/wall_ghosts.hpp"
#include "sluice/physics/damping.hpp"
#include "sluice/physics/eos.hpp"

using namespace sluice;

namespace {

Region box_region(const Vec3& min, const Vec3& max) {
  Region r;
  r.min = min;
  r.max = max;
  return r;
}

}  // namespace

TEST(Polygon, ContainsAndClosestBoundaryPoint) {
  const Polygon box = Polygon::box({0.0, 0.0}, {2.0, 1.0});
  EXPECT_TRUE(box.contains({1.0, 0.5}));
  EXPECT_FALSE(box.contains({2.5, 0.5}));
  EXPECT_FALSE(box.contains({1.0, -0.1}));
  const Vec2 c = box.closest_boundary_point({1.9, 0.5});
  EXPECT_DOUBLE_EQ(c[0], 2.0);
  EXPECT_DOUBLE_EQ(c[1], 0.5);
  EXPECT_DOUBLE_EQ(box.area(), 2.0);
  const Polygon triangle({{0.0, 0.0}, {4.0, 0.0}, {4.0, 2.0}});  // a 1:2 slope
  EXPECT_TRUE(triangle.contains({3.0, 1.0}));
  EXPECT_FALSE(triangle.contains({1.0, 1.0}));
  EXPECT_NEAR(triangle.distance_to_boundary({2.0, 1.0}), 0.0, 1e-12);
}

TEST(Setup, DefaultTankHasThreeWallLayersAtDxSpacing) {
  const Case c = *load_builtin_case("dam_break");
  EXPECT_EQ(wall_layers(c), 3);  // 2h = 0.52 m at dx = 0.2 m
  const sluice::Setup<2> s = build_setup<2>(c);
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
  c.walls.push_back(box_region({5.0, 0.0, 0.0}, {6.0, 1.0, 0.0}));
  const sluice::Setup<2> s = build_setup<2>(c);
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

// The hydrostatic start in each lattice column: the k-th fluid particle from the top has the pressure
// of the water above it, rho0 g (k + 1/2) dx per unit area; the column is squeezed onto its bottom so
// that each particle's volume m / rho fills the space it has (spacing dx rho0 / rho between
// neighbours, half of that under the lowest); the bottom edge stays on the floor.
void expect_hydrostatic_columns(const sluice::Setup<2>& s, const Case& c, std::size_t columns_expected) {
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  const double g = 9.81;
  std::map<long, std::vector<std::size_t>> columns;
  for (std::size_t i = 0; i < s.particles.size(); ++i)
    if (s.particles.is_fluid(i)) columns[std::lround(s.particles.position[0][i] / c.dx - 0.5)].push_back(i);
  ASSERT_EQ(columns.size(), columns_expected);
  for (auto& [column, members] : columns) {
    const auto& y = s.particles.position[1];
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) { return y[a] > y[b]; });
    for (std::size_t k = 0; k < members.size(); ++k) {
      const std::size_t i = members[k];
      const double rho = s.particles.density[i];
      EXPECT_NEAR(eos.pressure(rho), c.rest_density * g * (k + 0.5) * c.dx, 1e-6) << "column " << column << ", " << k;
      if (k + 1 < members.size()) {
        const std::size_t below = members[k + 1];
        const double mid = eos.density(c.rest_density * g * (k + 1.0) * c.dx);  // at the mass between them
        EXPECT_NEAR(y[i] - y[below], c.dx * c.rest_density / mid, 1e-4 * c.dx) << "column " << column << ", " << k;
      }
    }
    const double bottom_rho = eos.density(c.rest_density * g * (members.size() - 0.25) * c.dx);
    EXPECT_NEAR(y[members.back()], 0.5 * c.dx * c.rest_density / bottom_rho, 1e-4 * c.dx) << "column " << column;
  }
}

TEST(Setup, HydrostaticStartMatchesTheTaitEquationAtDepth) {
  const Case c = *load_builtin_case("dam_break");
  const sluice::Setup<2> s = build_setup<2>(c);
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const double x = s.particles.position[0][i], y = s.particles.position[1][i];
    if (!s.particles.is_fluid(i)) continue;
    const double surface = x < 3.0 ? 5.0 : 2.0;
    EXPECT_NEAR(eos.pressure(s.particles.density[i]), c.rest_density * 9.81 * (surface - y), 1e-6) << x << ", " << y;
    EXPECT_NEAR(std::fmod(y, c.dx), 0.5 * c.dx, 1e-9);  // on the lattice
  }
}

// gamma = 1 (k = 1 - 1/gamma = 0) is the limit of the closed form, which divided 0 by 0 there; gamma just
// above 1 would lose all its digits to cancellation in it.
class HydrostaticSqueeze : public ::testing::TestWithParam<double> {};
INSTANTIATE_TEST_SUITE_P(Gamma, HydrostaticSqueeze, ::testing::Values(7.0, 1.0, 1.0 + 1e-9, 1.5));

TEST_P(HydrostaticSqueeze, GivesEachParticleTheWeightAboveItAndItsCompressedSpacing) {
  Case c = *load_builtin_case("dam_break");  // c0 = 20 m/s: the 5 m column is 9 % denser at the bottom
  c.hydrostatic_squeeze = true;
  c.gamma = GetParam();
  const sluice::Setup<2> s = build_setup<2>(c);
  expect_hydrostatic_columns(s, c, 100);
  // The squeezed height of a column H deep: D(H) = int_0^H rho0 / rho(rho0 g s) ds; 4.76 m for the 5 m
  // column and 1.955 m for the 2 m layer (g H^2 / (2 c0^2) would say 0.31 m and 0.05 m lower: the
  // Tait equation stiffens as it is compressed).
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  auto squeezed = [&](double depth) {
    const int n = 100000;
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += c.rest_density / eos.density(c.rest_density * 9.81 * (k + 0.5) * depth / n);
    return sum * depth / n;
  };
  double top_column = 0.0, top_layer = 0.0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (!s.particles.is_fluid(i)) continue;
    const double x = s.particles.position[0][i], y = s.particles.position[1][i];
    (x < 3.0 ? top_column : top_layer) = std::max(x < 3.0 ? top_column : top_layer, y + 0.5 * c.dx);
  }
  EXPECT_NEAR(top_column, squeezed(5.0), 1e-3);
  EXPECT_NEAR(top_layer, squeezed(2.0), 1e-3);
  EXPECT_LT(top_column, 4.8);
}

TEST(TaitEos, ATensionOfTheStiffnessOrMoreHasZeroDensityNotNaN) {
  const TaitEos eos{1000.0, 20.0, 7.0};
  EXPECT_DOUBLE_EQ(eos.density(0.0), 1000.0);
  EXPECT_GT(eos.density(-0.99 * eos.stiffness()), 0.0);
  EXPECT_EQ(eos.density(-eos.stiffness()), 0.0);
  EXPECT_EQ(eos.density(-10.0 * eos.stiffness()), 0.0);
}

TEST(Setup, WithoutHydrostaticStartTheWaterStaysOnTheLatticeAtRestDensity) {
  Case c = *load_builtin_case("dam_break");
  c.hydrostatic_start = false;
  const sluice::Setup<2> s = build_setup<2>(c);
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (!s.particles.is_fluid(i)) continue;
    EXPECT_EQ(s.particles.density[i], c.rest_density);
    EXPECT_NEAR(std::fmod(s.particles.position[1][i], c.dx), 0.5 * c.dx, 1e-9);
  }
}

TEST(Leaks, AParticleInsideAWallIsPutBackWithItsNormalVelocityReversed) {
  Particles<2> p;
  p.add({0.5, -0.03}, Kind::fluid, 1000.0);  // 3 cm into the floor of a tank
  p.velocity[0][0] = 1.0;
  p.velocity[1][0] = -2.0;
  p.add({0.5, 0.5}, Kind::fluid, 1000.0);  // in the water: untouched
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon::box({-0.3, -0.3}, {2.3, 0.0}))};
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

// The checks over a range of particles (the solver's sweeps): only the range is touched, and a
// particle the skip mask marks (another process's ghost) is left to its owner.
TEST(Leaks, TheRangeChecksTouchOnlyTheirRangeAndSkipTheMarked) {
  Particles<2> p;
  for (int k = 0; k < 4; ++k) p.add({0.2 + 0.2 * k, -0.03}, Kind::fluid, 1000.0);  // all 3 cm into the floor
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon::box({-0.3, -0.3}, {2.3, 0.0}))};
  const double dx = 0.1;
  const WallChecks<2> checks(solids, dx, nullptr);
  const std::vector<std::uint8_t> ghost = {0, 1, 0, 0};
  EXPECT_EQ(checks.put_back(p, 0, 3, ghost.data()), 2);  // particles 0 and 2; 1 is skipped, 3 outside
  EXPECT_NEAR(p.position[1][0], 0.5 * dx, 1e-12);
  EXPECT_EQ(p.position[1][1], -0.03);
  EXPECT_NEAR(p.position[1][2], 0.5 * dx, 1e-12);
  EXPECT_EQ(p.position[1][3], -0.03);
  EXPECT_EQ(checks.put_back(p, 0, 4), 2);  // the rest, without a mask
  // A reach short of the dx/4 band cannot tell which particles the stops may skip.
  const SolidReach<2> short_reach(solids, {-0.5, -0.5}, {2.5, 1.0}, 0.2, 0.01);
  EXPECT_THROW(WallChecks<2>(solids, dx, &short_reach), std::invalid_argument);
}

TEST(Solids, BoxesSayTheyAreBoxes) {
  EXPECT_TRUE(Polygon::box({0.0, 0.0}, {1.0, 2.0}).is_box());
  EXPECT_TRUE(Polygon({{1.0, 2.0}, {0.0, 2.0}, {0.0, 0.0}, {1.0, 0.0}}).is_box());  // clockwise
  EXPECT_FALSE(Polygon({{0.0, 0.0}, {1.0, 0.0}, {1.0, 2.0}, {0.0, 1.0}}).is_box());
  EXPECT_FALSE(Polygon({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}, {0.0, 0.5}}).is_box());
  EXPECT_FALSE(Polygon({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {1.0, 0.0}}).is_box());  // a corner missing
  EXPECT_TRUE(Box<3>({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}).is_box());
}

TEST(NoPenetration, WaterCloseToAWallLosesItsApproachAndNothingElse) {
  // A floor at y = 0, dx = 0.1: the band is y < dx/4 = 0.025.
  const double dx = 0.1;
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon::box({-0.3, -0.3}, {2.3, 0.0}))};
  Particles<2> p;
  const auto add = [&](double x, double y, double vx, double vy) {
    p.add({x, y}, Kind::fluid, 1000.0);
    p.velocity[0].back() = vx;
    p.velocity[1].back() = vy;
  };
  add(0.5, 0.0, 1.0, -2.0);      // 0: on the surface, moving in: the approach stops (f = 1)
  add(0.6, 0.0125, 1.0, -2.0);   // 1: half way through the band: half of it goes (f = 0.5)
  add(0.7, -0.025, 1.0, -2.0);   // 2: a quarter spacing inside: reflected (f = 2)
  add(0.8, -0.05, 0.0, -2.0);    // 3: deeper inside: still reflected (f clamped at 2)
  add(0.9, 0.01, 1.0, 2.0);      // 4: moving away from the wall: untouched
  add(1.0, 0.05, 0.0, -2.0);     // 5: at dx/2, where water at rest sits: untouched
  add(1.1, 0.0, 0.0, -2.0);      // 6: a wall particle: untouched
  p.kind.back() = Kind::wall;
  EXPECT_EQ(stop_wall_approach(p, solids, dx, nullptr, 0.0), 4u);
  const double expected_vy[] = {0.0, -1.0, 2.0, 2.0, 2.0, -2.0, -2.0};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double expected_vx = i == 0 || i == 1 || i == 2 || i == 4 ? 1.0 : 0.0;  // the tangential part stays
    EXPECT_NEAR(p.velocity[1][i], expected_vy[i], 1e-9) << "particle " << i;
    EXPECT_NEAR(p.velocity[0][i], expected_vx, 1e-9) << "particle " << i;
  }
}

TEST(NoPenetration, InACornerThatWrapsAroundTheWaterBothFacesStopTheApproach) {
  // A U-shaped solid (a tank's floor and side walls as one polygon); its inner corner at (0, 0) is a
  // reflex vertex. A particle in the corner, within dx/4 of both faces, moving diagonally into it:
  // both parts of the approach go, not only the one towards the nearest face.
  const double dx = 0.1;
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon(
      {{-0.2, -0.2}, {1.2, -0.2}, {1.2, 1.0}, {1.0, 1.0}, {1.0, 0.0}, {0.0, 0.0}, {0.0, 1.0}, {-0.2, 1.0}}))};
  Particles<2> p;
  p.add({0.01, 0.02}, Kind::fluid, 1000.0);  // nearer the left face than the floor
  p.add({0.5, 0.01}, Kind::fluid, 1000.0);   // on the middle of the floor: one face only
  for (std::size_t i = 0; i < p.size(); ++i) p.velocity[0][i] = p.velocity[1][i] = -1.0;
  EXPECT_EQ(stop_wall_approach(p, solids, dx, nullptr, 0.0), 2u);
  // f = 1 - distance / band of the approach goes, per face: distance / band of it stays.
  EXPECT_NEAR(p.velocity[0][0], -0.01 / 0.025, 1e-12);
  EXPECT_NEAR(p.velocity[1][0], -0.02 / 0.025, 1e-12);
  EXPECT_EQ(p.velocity[0][1], -1.0);  // along the floor: untouched
  EXPECT_NEAR(p.velocity[1][1], -0.01 / 0.025, 1e-12);
}

TEST(Polygon, FacesOutsideOfWhichAPointLiesAreTheCornersOnesOnlyWhereTheSolidWrapsAround) {
  const auto faces = [](const Polygon& shape, Vec2 x, double reach) {
    std::vector<std::pair<Vec2, Vec2>> found;
    shape.for_each_face_outside(x, reach, [&](const Vec2& q, const Vec2& n) { found.emplace_back(q, n); });
    return found;
  };
  // Clockwise on purpose: the normals point out of the solid either way.
  const Polygon u({{-0.2, 1.0}, {0.0, 1.0}, {0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {1.2, 1.0}, {1.2, -0.2}, {-0.2, -0.2}});
  const auto corner = faces(u, {0.01, 0.02}, 0.025);
  ASSERT_EQ(corner.size(), 2u);
  for (const auto& [q, n] : corner) {
    const bool left = n[0] > 0.5;
    const Vec2 foot = left ? Vec2{0.0, 0.02} : Vec2{0.01, 0.0};
    EXPECT_NEAR(norm(q - foot), 0.0, 1e-12);
    const Vec2 normal = left ? Vec2{1.0, 0.0} : Vec2{0.0, 1.0};
    EXPECT_EQ(n, normal);
  }
  EXPECT_EQ(faces(u, {0.01, 0.02}, 0.015).size(), 1u);  // the floor is beyond the reach
  EXPECT_TRUE(faces(u, {0.5, 0.5}, 0.025).empty());
  EXPECT_TRUE(faces(u, {-0.1, -0.1}, 0.5).empty());     // inside the solid
  // Outside a convex corner, even an acute one, a point is outside of one face at most.
  const Polygon wedge({{0.0, 0.0}, {1.0, 0.0}, {1.0, 0.5774}});
  for (const Vec2 x : {Vec2{-0.01, -0.001}, Vec2{0.5, -0.01}, Vec2{-0.001, 0.0005}, Vec2{0.02, 0.02}})
    EXPECT_LE(faces(wedge, x, 0.1).size(), 1u) << x[0] << ", " << x[1];
}

TEST(NoPenetration, TheDriftVelocityDecidesWithTheLeapfrogsHalfKick) {
  // At rest on the surface of a 3D floor, but the half kick tau a would carry the particle in: the
  // velocity takes minus that approach (the drift velocity v + tau a then has no normal part).
  const Solids<3> solids = {std::make_shared<Box<3>>(Vec<3>{-0.3, -0.3, -0.3}, Vec<3>{1.3, 0.9, 0.0})};
  Particles<3> p;
  p.add({0.5, 0.4, 0.0}, Kind::fluid, 1000.0);
  p.add({0.5, 0.2, 0.0}, Kind::fluid, 1000.0);
  Particles<3>::Vector<double> a;
  for (auto& component : a) component.assign(2, 0.0);
  a[2][0] = -10.0;  // pulled down
  a[2][1] = +10.0;  // pushed up
  EXPECT_EQ(stop_wall_approach(p, solids, 0.1, &a, 0.01), 1u);
  EXPECT_NEAR(p.velocity[2][0] + 0.01 * a[2][0], 0.0, 1e-12);
  EXPECT_EQ(p.velocity[2][1], 0.0);
  EXPECT_EQ(stop_wall_approach(p, solids, 0.1, nullptr, 0.0), 0u);  // moving up now: nothing to stop
}

// SolidReach (geometry/leaks.hpp): the cells where the leak checks skip the water.
namespace {

// Points spread over the box [lower - 0.1, upper + 0.1], a fixed sequence.
template <int Dim>
std::vector<Vec<Dim>> spread_points(const Vec<Dim>& lower, const Vec<Dim>& upper, std::size_t count) {
  std::mt19937_64 random(7);
  std::vector<Vec<Dim>> points(count);
  for (auto& x : points)
    for (int d = 0; d < Dim; ++d)
      x[d] = std::uniform_real_distribution<double>(lower[d] - 0.1, upper[d] + 0.1)(random);
  return points;
}

template <int Dim>
void expect_clear_cells_far_from_every_solid(const Case& c) {
  const sluice::Setup<Dim> s = build_setup<Dim>(c);
  ASSERT_FALSE(s.solids.empty());
  const double reach = 0.25 * c.dx;
  Vec<Dim> lower{}, upper{};
  const Vec3 size = c.tank_size();
  for (int d = 0; d < Dim; ++d) {
    lower[d] = -0.5;
    upper[d] = size[d] + 0.5;
  }
  const SolidReach<Dim> near(s.solids, lower, upper, 2.0 * c.smoothing_length(), reach);
  // Most of the tank is clear (else the checks skip nothing), not all of it (the walls are not).
  EXPECT_GT(near.clear_fraction(), 0.3);
  EXPECT_LT(near.clear_fraction(), 0.95);
  std::size_t clear = 0;
  for (const Vec<Dim>& x : spread_points<Dim>(lower, upper, 20000)) {
    if (!near.clear(x)) continue;
    ++clear;
    for (const auto& solid : s.solids) EXPECT_GT(solid->signed_distance(x), reach);
  }
  EXPECT_GT(clear, 2000u);
  // Every wall particle is inside a solid: never in a clear cell.
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (s.particles.is_fluid(i)) continue;
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = s.particles.position[d][i];
    EXPECT_FALSE(near.clear(x));
  }
  Vec<Dim> outside = lower;
  outside[0] -= 1.0;
  EXPECT_FALSE(near.clear(outside));
  Vec<Dim> nan = lower;
  nan[Dim - 1] = std::nan("");
  EXPECT_FALSE(near.clear(nan));
  // Past the grid's far side on one axis (its cells may reach a cell past `upper`), with the others in
  // clear water: not clear.
  Vec<Dim> middle{};
  for (int d = 0; d < Dim; ++d) middle[d] = 0.5 * size[d];
  ASSERT_TRUE(near.clear(middle));
  for (int d = 0; d < Dim; ++d) {
    Vec<Dim> past = middle;
    past[d] = upper[d] + (upper[d] - lower[d]);
    EXPECT_FALSE(near.clear(past)) << "axis " << d;
  }
  EXPECT_FALSE(SolidReach<Dim>{}.clear(middle));  // default-constructed: nothing is clear
}

}  // namespace

TEST(SolidReach, AClearCellIsFartherThanItsReachFromEverySolid) {
  expect_clear_cells_far_from_every_solid<2>(*load_builtin_case("dam_break"));
  Case spheric2 = *load_builtin_case("spheric2");  // with its box obstacle
  spheric2.dx = 0.05;
  expect_clear_cells_far_from_every_solid<3>(spheric2);
}

// Water everywhere, inside the walls too, moving every way: the put-back and the stopped approach
// with the clear cells skipped leave every particle as the full checks do.
TEST(SolidReach, SkippingTheClearCellsChangesNothing) {
  const Case c = *load_builtin_case("dam_break");
  const sluice::Setup<2> s = build_setup<2>(c);
  const Vec<2> lower{-1.0, -1.0}, upper{c.tank_width + 1.0, c.tank_height + 1.0};
  const SolidReach<2> near(s.solids, lower, upper, 2.0 * c.smoothing_length(), 0.25 * c.dx);
  Particles<2> p;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> speed(-3.0, 3.0);
  for (const Vec<2>& x : spread_points<2>(lower, upper, 40000)) {
    p.add(x, Kind::fluid, 1000.0);
    p.velocity[0].back() = speed(random);
    p.velocity[1].back() = speed(random);
  }
  Particles<2> q = p;
  const std::size_t stopped = stop_wall_approach(p, s.solids, c.dx, nullptr, 0.0);
  EXPECT_GT(stopped, 20u);
  EXPECT_EQ(stop_wall_approach(q, s.solids, c.dx, nullptr, 0.0, 1, &near), stopped);
  const std::size_t put_back = put_back_leaked(p, s.solids, c.dx);
  EXPECT_GT(put_back, 1000u);
  EXPECT_EQ(put_back_leaked(q, s.solids, c.dx, 1, &near), put_back);
  for (int d = 0; d < 2; ++d) {
    EXPECT_EQ(p.position[d], q.position[d]);
    EXPECT_EQ(p.velocity[d], q.velocity[d]);
  }
  EXPECT_EQ(p.needs_density_repair, q.needs_density_repair);
  // A reach below the approach band would skip particles inside it.
  const SolidReach<2> short_reach(s.solids, lower, upper, 2.0 * c.smoothing_length(), 0.0);
  EXPECT_THROW(stop_wall_approach(q, s.solids, c.dx, nullptr, 0.0, 1, &short_reach), std::invalid_argument);
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

// ---------------------------------------------------------------------------------------------
// The solid interface in 3D

TEST(Box, InsideSignedDistanceAndClosestPointWithOutwardNormal) {
  const Box<3> box({0.0, 0.0, 0.0}, {2.0, 1.0, 1.0});
  EXPECT_TRUE(box.contains({1.0, 0.5, 0.5}));
  EXPECT_FALSE(box.contains({1.0, 0.5, 1.5}));
  EXPECT_DOUBLE_EQ(box.signed_distance({1.0, 0.5, 0.9}), -0.1);
  EXPECT_DOUBLE_EQ(box.signed_distance({3.0, 0.5, 0.5}), 1.0);
  EXPECT_DOUBLE_EQ(box.signed_distance({3.0, 2.0, 0.5}), std::sqrt(2.0));  // off an edge
  const SurfacePoint<3> inside = box.closest_surface_point({1.0, 0.5, 0.9});
  EXPECT_DOUBLE_EQ(inside.point[2], 1.0);
  EXPECT_EQ(inside.normal, (Vec<3>{0.0, 0.0, 1.0}));
  const SurfacePoint<3> outside = box.closest_surface_point({1.0, -0.5, 0.5});
  EXPECT_DOUBLE_EQ(outside.point[1], 0.0);
  EXPECT_EQ(outside.normal, (Vec<3>{0.0, -1.0, 0.0}));
}

TEST(Polygon, SignedDistanceAndOutwardNormal) {
  const Polygon box = Polygon::box({0.0, 0.0}, {2.0, 1.0});
  EXPECT_DOUBLE_EQ(box.signed_distance({1.0, 0.9}), -0.1);
  EXPECT_DOUBLE_EQ(box.signed_distance({1.0, 1.5}), 0.5);
  EXPECT_NEAR(box.closest_surface_point({1.0, 0.9}).normal[1], 1.0, 1e-12);
  EXPECT_NEAR(box.closest_surface_point({1.0, 1.5}).normal[1], 1.0, 1e-12);
  EXPECT_NEAR(box.closest_surface_point({-0.5, 0.5}).normal[0], -1.0, 1e-12);
}

Case box_tank_3d(double dx) {
  return parse_case("[domain]\ndimension = 3\ndx = " + std::to_string(dx) +
                        "\n[tank]\nwidth = 1.0\ndepth = 0.6\nheight = 0.8\n"
                        "[[water]]\nmin = [0, 0, 0]\nmax = [0.4, 0.6, 0.5]\n",
                    "3D box tank");
}

// A region the lattice fills with more than 1 % less (or more) water than it holds gets a note
// saying how much; one it fills exactly gets none, and neither does one a solid takes part of.
TEST(Setup, ANoteSaysHowMuchLessWaterTheLatticeHolds) {
  // 0.4 x 0.6 x 0.5 m at dx = 0.1: 4 x 6 x 5 points, exactly the box.
  EXPECT_TRUE(build_setup<3>(box_tank_3d(0.1)).notes.empty());
  // At dx = 0.12: 3 x 5 x 4 points hold 0.10368 m^3 of the box's 0.12, 13.6 % less.
  const sluice::Setup<3> s = build_setup<3>(box_tank_3d(0.12));
  ASSERT_EQ(s.notes.size(), 1u);
  for (const char* part : {"[[water]] number 1 (box from [0, 0, 0] to [0.4, 0.6, 0.5])", "60 particles",
                           "0.1037 m^3", "13.6 % less than the region's 0.12 m^3", "domain.dx = 0.12 m"})
    EXPECT_NE(s.notes[0].find(part), std::string::npos) << part << " not in: " << s.notes[0];
  // Overlapping regions: the points met twice are removed, and a note counts them.
  Case twice = box_tank_3d(0.1);
  twice.water.push_back(twice.water[0]);
  const sluice::Setup<3> merged = build_setup<3>(twice);
  ASSERT_EQ(merged.notes.size(), 1u);
  EXPECT_NE(merged.notes[0].find("120 water particles removed at set-up"), std::string::npos) << merged.notes[0];
}

// A water region that holds no point of the lattice is an error, whatever its shape (a box that thin
// is already refused by the case checks, with the case file's name).
TEST(Setup, AWaterRegionWithoutWaterIsAnError) {
  Case c = box_tank_3d(0.1);
  c.water[0].min = {0.0, 0.0, 0.0};
  c.water[0].max = {0.4, 0.6, 0.04};  // below the first layer of points, at 0.05 m
  try {
    build_setup<3>(c);
    ADD_FAILURE() << "expected a CaseError";
  } catch (const CaseError& e) {
    const std::string what = e.what();
    for (const char* part : {"[[water]] number 1 (box from [0, 0, 0] to [0.4, 0.6, 0.04])", "holds no water particle",
                             "domain.dx = 0.1 m"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " not in: " << what;
  }
}

TEST(Setup, ThreeDimensionalTankHasItsWallLayersOnEveryFaceAndNoDuplicates) {
  const Case c = box_tank_3d(0.1);
  const int layers = wall_layers(c);  // 2h = 0.26 m: 3 layers
  ASSERT_EQ(layers, 3);
  const sluice::Setup<3> s = build_setup<3>(c);
  EXPECT_EQ(s.removed_near_coincident, 0u);  // the slabs do not overlap
  std::size_t walls = 0, fluid = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) (s.particles.is_fluid(i) ? fluid : walls)++;
  // The wall lattice is the box [-0.3, 1.3] x [-0.3, 0.9] x [-0.3, 1.1] (16 x 12 x 14 points) minus
  // the inside (10 x 6 x 8).
  EXPECT_EQ(walls, 16u * 12u * 14u - 10u * 6u * 8u);
  EXPECT_EQ(fluid, 4u * 6u * 5u);
  // Every wall particle lies behind the nearest inner face by (k + 1/2) dx, k < layers.
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (s.particles.is_fluid(i)) continue;
    const double x = s.particles.position[0][i], y = s.particles.position[1][i], z = s.particles.position[2][i];
    const double depth = std::max({-x, x - c.tank_width, -y, y - c.tank_depth, -z, z - c.tank_height});
    EXPECT_GT(depth, 0.0);
    EXPECT_LT(depth, layers * c.dx);
    EXPECT_NEAR(std::fmod(depth + 1e-9, c.dx), 0.5 * c.dx, 1e-6);
  }
  EXPECT_EQ(s.solids.size(), 6u);  // floor, four sides, lid
}

TEST(Setup, ThreeDimensionalHydrostaticStartAlongZ) {
  const Case c = box_tank_3d(0.1);
  const sluice::Setup<3> s = build_setup<3>(c);
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (!s.particles.is_fluid(i)) continue;
    EXPECT_NEAR(eos.pressure(s.particles.density[i]), c.rest_density * 9.81 * (0.5 - s.particles.position[2][i]), 1e-6);
  }
}

TEST(Setup, ThreeDimensionalHydrostaticSqueezeAlongZ) {
  // Each fluid particle has the weight of the water above it on the lattice, rho0 g (0.5 - z_lattice),
  // z_lattice its height before the column was squeezed; it moves down by less than g H^2 / (2 c0^2).
  Case c = box_tank_3d(0.1);
  c.hydrostatic_squeeze = true;
  const sluice::Setup<3> s = build_setup<3>(c);
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (!s.particles.is_fluid(i)) continue;
    const double z = s.particles.position[2][i];
    const double z_lattice = (std::floor(z / c.dx) + 1.0) * c.dx - 0.5 * c.dx;
    EXPECT_NEAR(eos.pressure(s.particles.density[i]), c.rest_density * 9.81 * (0.5 - z_lattice), 1e-6);
    EXPECT_LE(z, z_lattice);
    EXPECT_GT(z, z_lattice - 9.81 * 0.25 / (2.0 * c.sound_speed * c.sound_speed));
  }
}

TEST(Leaks, ThreeDimensionalPutBackThroughTheNearestFace) {
  Particles<3> p;
  p.add({0.5, 0.4, -0.03}, Kind::fluid, 1000.0);
  p.velocity[2][0] = -2.0;
  const Solids<3> solids = {std::make_shared<Box<3>>(Vec<3>{-0.3, -0.3, -0.3}, Vec<3>{1.3, 0.9, 0.0})};
  EXPECT_EQ(put_back_leaked(p, solids, 0.1), 1u);
  EXPECT_NEAR(p.position[2][0], 0.05, 1e-12);
  EXPECT_NEAR(p.velocity[2][0], 2.0, 1e-12);
  EXPECT_EQ(p.needs_density_repair[0], 1);
}

// mDBC ghost nodes (geometry/wall_ghosts.hpp): the mirror image of each wall particle through the
// nearest surface the water touches.
namespace {

Vec2 ghost_of(const WallGhosts<2>& g, const Particles<2>& p, double x, double y) {
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_fluid(i) && std::abs(p.position[0][i] - x) < 1e-9 && std::abs(p.position[1][i] - y) < 1e-9) {
      EXPECT_TRUE(g.of(p.id[i])) << "no ghost at " << x << ", " << y;
      return g.node[p.id[i]];
    }
  ADD_FAILURE() << "no wall particle at " << x << ", " << y;
  return {};
}

// The walls of a tank that moves, as one solid: everything outside the inside [0, size] (open upwards
// without a lid). Inside, the distance to the nearest face and its normal into the tank; in the walls,
// minus the distance to the inside; in a corner both faces are within reach; the bounds are the wall
// layers' (to the side walls' top when open).
TEST(TankWalls, TheOutsideOfTheTanksInside) {
  const TankWalls<2> closed(Vec<2>{0.6, 0.3}, true, 0.04);
  EXPECT_FALSE(closed.contains({0.3, 0.1}));
  EXPECT_TRUE(closed.contains({-0.01, 0.1}));
  EXPECT_TRUE(closed.contains({0.3, 0.31}));
  EXPECT_DOUBLE_EQ(closed.signed_distance({0.3, 0.02}), 0.02);
  EXPECT_NEAR(closed.signed_distance({0.3, 0.27}), 0.03, 1e-15);
  EXPECT_NEAR(closed.signed_distance({-0.03, -0.04}), -0.05, 1e-15);
  const SurfacePoint<2> floor = closed.closest_surface_point({0.3, 0.02});
  EXPECT_EQ(floor.point[1], 0.0);
  EXPECT_EQ(floor.normal[1], 1.0);
  const SurfacePoint<2> lid = closed.closest_surface_point({0.3, 0.29});
  EXPECT_EQ(lid.point[1], 0.3);
  EXPECT_EQ(lid.normal[1], -1.0);
  const SurfacePoint<2> below = closed.closest_surface_point({0.2, -0.02});
  EXPECT_EQ(below.point[1], 0.0);
  EXPECT_EQ(below.normal[1], 1.0);  // out of the walls, into the tank
  int faces = 0;
  closed.for_each_face_outside({0.001, 0.002}, 0.005, [&](const Vec<2>& foot, const Vec<2>& normal) {
    ++faces;
    EXPECT_NEAR(foot[0] * normal[0] + foot[1] * normal[1], 0.0, 1e-15);
  });
  EXPECT_EQ(faces, 2);
  EXPECT_NEAR(closed.lower()[0], -0.04, 1e-15);
  EXPECT_NEAR(closed.upper()[1], 0.34, 1e-15);

  const TankWalls<2> open(Vec<2>{0.6, 0.3}, false, 0.04);
  EXPECT_FALSE(open.contains({0.3, 0.5}));  // above an open tank is not wall
  EXPECT_TRUE(open.contains({0.61, 0.5}) && open.contains({0.3, -0.01}));
  EXPECT_NEAR(open.upper()[1], 0.3, 1e-15);
  const TankWalls<3> box(Vec<3>{1.0, 0.5, 0.4}, true, 0.05);
  faces = 0;
  box.for_each_face_outside({0.001, 0.499, 0.399}, 0.01, [&](const Vec<3>&, const Vec<3>&) { ++faces; });
  EXPECT_EQ(faces, 3);  // a corner of the box: three faces
}

// [damping]: water before the zone keeps its velocity; in it the velocity is multiplied by
// exp(-strength s^2 dt), s = depth / length, and beyond its end by exp(-strength dt); walls are not
// touched; the direction is normalised.
TEST(Damping, RelaxesTheWatersVelocityQuadraticallyAcrossTheZone) {
  Case c;
  c.dimension = 2;
  c.damping_length = 2.0;
  c.damping_start = {4.0, 0.0, 0.0};
  c.damping_direction = {3.0, 0.0, 0.0};
  c.damping_strength = 10.0;
  const DampingZone<2> zone = DampingZone<2>::of(c);
  Particles<2> p;
  for (double x : {3.0, 4.0, 4.5, 5.0, 6.0, 7.0}) {
    p.add({x, 0.1}, Kind::fluid, 1000.0);
    p.velocity[0][p.size() - 1] = 1.0;
    p.velocity[1][p.size() - 1] = -0.5;
  }
  p.add({5.0, -0.02}, Kind::wall, 1000.0);
  p.velocity[0][p.size() - 1] = 1.0;
  const double dt = 1e-3;
  apply_damping(p, p.size(), zone, dt, 1);
  const double expected[] = {1.0, 1.0, std::exp(-10.0 * dt * 0.0625), std::exp(-10.0 * dt * 0.25), std::exp(-10.0 * dt),
                             std::exp(-10.0 * dt)};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(p.velocity[0][i], expected[i]) << "x = " << p.position[0][i];
    EXPECT_DOUBLE_EQ(p.velocity[1][i], -0.5 * expected[i]);
  }
  EXPECT_EQ(p.velocity[0][6], 1.0);
  // However strong, a step never reverses the velocity.
  c.damping_strength = 1e9;
  apply_damping(p, p.size(), DampingZone<2>::of(c), dt, 1);
  EXPECT_GE(p.velocity[0][5], 0.0);
}

}  // namespace

TEST(WallGhosts, MirroredThroughTheNearestWetSurfaceAndThroughCorners) {
  Case c = *load_builtin_case("dam_break");  // dx = 0.2, three layers
  c.walls.push_back(box_region({9.0, 0.0, 0.0}, {10.0, 1.0, 0.0}));  // a block on the floor
  const sluice::Setup<2> s = build_setup<2>(c);
  const WallGhosts<2> g = wall_ghosts(s.particles, c);
  auto expect_ghost = [&](double x, double y, double gx, double gy) {
    const Vec2 ghost = ghost_of(g, s.particles, x, y);
    EXPECT_NEAR(ghost[0], gx, 1e-9) << "wall particle at " << x << ", " << y;
    EXPECT_NEAR(ghost[1], gy, 1e-9) << "wall particle at " << x << ", " << y;
  };
  expect_ghost(5.1, -0.1, 5.1, 0.1);    // floor: through the floor
  expect_ghost(5.1, -0.5, 5.1, 0.5);    // its third layer
  expect_ghost(-0.3, 1.1, 0.3, 1.1);    // left wall
  expect_ghost(20.1, 3.1, 19.9, 3.1);   // right wall
  expect_ghost(5.1, 10.1, 5.1, 9.9);    // lid
  expect_ghost(-0.1, -0.1, 0.1, 0.1);   // the tank's corner: through the corner point
  expect_ghost(-0.3, -0.1, 0.3, 0.1);
  expect_ghost(9.1, 0.3, 8.9, 0.3);     // the block: through its near face, not the covered bottom
  expect_ghost(9.3, 0.3, 8.7, 0.3);     // equally near the bottom, which the floor covers
  expect_ghost(9.5, 0.9, 9.5, 1.1);     // through its top
  expect_ghost(8.9, -0.1, 8.9, 0.1);    // the floor in front of the block
  expect_ghost(9.1, -0.1, 8.9, 0.1);    // the floor under the block's edge: through the corner at its foot
}

TEST(WallGhosts, ThreeDimensionalTankMirrorsThroughItsFacesEdgesAndCorners) {
  const Case c = box_tank_3d(0.1);
  const sluice::Setup<3> s = build_setup<3>(c);
  const WallGhosts<3> g = wall_ghosts(s.particles, c);
  std::size_t walls = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    if (s.particles.is_fluid(i)) continue;
    ++walls;
    ASSERT_TRUE(g.of(s.particles.id[i]));
    // The midpoint of particle and ghost is the nearest point of the tank's inside.
    const Vec<3> size{c.tank_width, c.tank_depth, c.tank_height};
    for (int d = 0; d < 3; ++d) {
      const double x = s.particles.position[d][i];
      EXPECT_NEAR(0.5 * (x + g.node[s.particles.id[i]][d]), std::clamp(x, 0.0, size[d]), 1e-9);
    }
  }
  EXPECT_GT(walls, 0u);
}
