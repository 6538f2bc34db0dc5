// Adami, Hu & Adams (2012) wall pressure extrapolation (physics/wall_boundary.hpp): a wall under still
// water with hydrostatic pressure gets the hydrostatic pressure at its own position; negative values are
// clamped; a wall particle with no fluid around it is at p = 0, rho = rho0; the EOS inversion round-trips.
// The mDBC walls (physics/mdbc.hpp) on the same scenes: the hydrostatic pressure at every layer the water
// reaches from the mirror images (rho0 beyond), no slip and free slip, the rho0 floor and the cap on
// the extrapolation.
#include <gtest/gtest.h>

#include <cmath>

#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/mdbc.hpp"
#include "sluice/physics/wall_boundary.hpp"

using namespace sluice;

namespace {

constexpr double rho0 = 1000.0, g = 9.81, dx = 0.02, width = 1.0, depth = 0.5;
const TaitEos eos{rho0, 30.0, 7.0};
const CubicSpline<2> kernel(1.3 * dx);

struct Scene {
  Particles<2> p;
  CellGrid<2> grid;
};

// A floor at y = 0 with `layers` rows of wall particles below it (centres at -dx/2, -3dx/2, ...), and
// water 0 <= y <= depth on the lattice (i + 1/2) dx with density rho_of(y). `far_wall` adds one wall
// particle far from all fluid, at density 1050.
template <class RhoOf>
Scene make_scene(RhoOf rho_of, int layers, bool far_wall, double wall_density = rho0) {
  Scene s;
  const int nx = static_cast<int>(std::lround(width / dx));
  for (int i = 0; i < nx; ++i)
    for (int l = 0; l < layers; ++l) s.p.add({(i + 0.5) * dx, -(l + 0.5) * dx}, Kind::wall, wall_density);
  const int ny = static_cast<int>(std::lround(depth / dx));
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) {
      const double y = (j + 0.5) * dx;
      s.p.add({(i + 0.5) * dx, y}, Kind::fluid, rho_of(y));
    }
  if (far_wall) s.p.add({0.5 * width, depth + 0.5}, Kind::wall, 1050.0);
  s.p.resize(s.p.size());
  for (std::size_t i = 0; i < s.p.size(); ++i) s.p.id[i] = static_cast<std::uint32_t>(i);
  s.grid = CellGrid<2>({-0.2, -0.2}, {width + 0.2, depth + 1.0}, 2.0 * kernel.h);
  s.grid.bin(s.p.position);
  std::vector<double> scratch;
  s.p.permute(s.grid.order(), scratch, false, 1);
  return s;
}

double hydrostatic_density(double y) { return eos.density(rho0 * g * (depth - y)); }

}  // namespace

TEST(WallBoundary, WallUnderStillWaterGetsTheHydrostaticPressureAtItsPosition) {
  Scene s = make_scene(hydrostatic_density, 3, false);
  extrapolate_wall_density(s.p, s.grid, kernel, eos, {0.0, -g}, 1);
  int checked = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const double x = s.p.position[0][i], y = s.p.position[1][i];
    // Wall particles under the middle of the water (the kernel support is full of fluid above them),
    // in the two layers the fluid reaches (a support of 2.6 dx reaches the third layer's top only).
    if (s.p.is_fluid(i) || x < 0.2 || x > 0.8 || y < -2.0 * dx) continue;
    const double expected = rho0 * g * (depth - y);
    const double p = eos.pressure(s.p.density[i]);
    EXPECT_NEAR(p, expected, 0.002 * expected) << "wall particle at (" << x << ", " << y << ")";
    ++checked;
  }
  EXPECT_EQ(checked, 2 * 30);
}

TEST(WallBoundary, WithoutTheGravityTermTheWallWouldReadTheFluidAverageInstead) {
  // The same scene without gravity in the extrapolation: the wall reads the kernel average of the fluid
  // pressure, which is lower than the hydrostatic pressure at the wall by about rho0 g (mean distance).
  Scene s = make_scene(hydrostatic_density, 1, false);
  extrapolate_wall_density(s.p, s.grid, kernel, eos, {0.0, 0.0}, 1);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.is_fluid(i) || s.p.position[0][i] < 0.2 || s.p.position[0][i] > 0.8) continue;
    const double expected = rho0 * g * (depth + 0.5 * dx);
    EXPECT_LT(eos.pressure(s.p.density[i]), expected - rho0 * g * 0.5 * dx);
  }
}

TEST(WallBoundary, NegativeExtrapolatedPressureIsClampedToZero) {
  // Water under tension (rho < rho0), no gravity: the extrapolation is negative, the wall gets p = 0.
  Scene s = make_scene([](double) { return 0.99 * rho0; }, 2, false, 1020.0);
  int checked = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.is_fluid(i)) continue;
    bool found = false;
    const double raw = extrapolated_wall_pressure(s.p, s.grid, kernel, eos, {0.0, 0.0}, i, found);
    ASSERT_TRUE(found);
    EXPECT_NEAR(raw, eos.pressure(0.99 * rho0), 1e-9 * std::abs(raw));
    EXPECT_LT(raw, 0.0);
    ++checked;
  }
  EXPECT_GT(checked, 0);
  extrapolate_wall_density(s.p, s.grid, kernel, eos, {0.0, 0.0}, 1);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.is_fluid(i)) continue;
    EXPECT_EQ(s.p.density[i], rho0);
  }
}

TEST(WallBoundary, WallParticleWithoutFluidNeighboursIsAtRestDensity) {
  Scene s = make_scene(hydrostatic_density, 2, true);
  std::size_t far = s.p.size();
  for (std::size_t i = 0; i < s.p.size(); ++i)
    if (!s.p.is_fluid(i) && s.p.position[1][i] > depth) far = i;
  ASSERT_LT(far, s.p.size());
  ASSERT_EQ(s.p.density[far], 1050.0);
  bool found = true;
  EXPECT_EQ(extrapolated_wall_pressure(s.p, s.grid, kernel, eos, {0.0, -g}, far, found), 0.0);
  EXPECT_FALSE(found);
  extrapolate_wall_density(s.p, s.grid, kernel, eos, {0.0, -g}, 1);
  EXPECT_EQ(s.p.density[far], rho0);
  EXPECT_EQ(eos.pressure(s.p.density[far]), 0.0);
}

TEST(WallBoundary, ResultsDoNotDependOnTheThreadCount) {
  Scene one = make_scene(hydrostatic_density, 3, true);
  Scene two = make_scene(hydrostatic_density, 3, true);
  extrapolate_wall_density(one.p, one.grid, kernel, eos, {0.0, -g}, 1);
  extrapolate_wall_density(two.p, two.grid, kernel, eos, {0.0, -g}, 2);
  EXPECT_EQ(one.p.density, two.p.density);
}

TEST(WallBoundary, TaitInversionRoundTrips) {
  EXPECT_EQ(eos.density(0.0), rho0);
  for (double p : {1.0, 100.0, 4905.0, 1e4, 1e5, 1e6}) {
    const double rho = eos.density(p);
    EXPECT_GT(rho, rho0);
    EXPECT_NEAR(eos.pressure(rho), p, 1e-9 * eos.stiffness());
  }
  for (double rho : {990.0, 1000.0, 1003.0, 1050.0}) EXPECT_NEAR(eos.density(eos.pressure(rho)), rho, 1e-9 * rho);
}

namespace {

// The floor's mirror images: the wall particle at (x, y < 0) has its ghost at (x, -y).
WallGhosts<2> floor_ghosts(const Particles<2>& p) {
  WallGhosts<2> g;
  g.node.resize(p.size());
  g.has.assign(p.size(), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_fluid(i) && p.position[1][i] < 0.0) {
      g.node[p.id[i]] = {p.position[0][i], -p.position[1][i]};
      g.has[p.id[i]] = 1;
    }
  return g;
}

constexpr double mass = rho0 * dx * dx;

MdbcWalls mdbc_of(const Scene& s, WallSlip slip) { return MdbcWalls::of(floor_ghosts(s.p), mass, slip); }

}  // namespace

TEST(Mdbc, EveryWallLayerTheWaterReachesGetsTheHydrostaticPressureAtItsPosition) {
  // The support is 2h = 2.6 dx: the water's lowest row, at dx/2, reaches the layers at -dx/2 and
  // -3dx/2 (1 and 2 dx away) but not the one at -5dx/2 (3 dx away), which takes part in no pair with
  // the water and holds rho0 and rest, as a dry wall does.
  Scene s = make_scene(hydrostatic_density, 3, false);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    if (!s.p.is_fluid(i)) s.p.density[i] = 1020.0, s.p.velocity[0][i] = 1.0;
  mdbc_of(s, WallSlip::free_slip).before_rates(s.p, s.grid, kernel, eos, {0.0, -g}, 1);
  int reached = 0, beyond = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const double x = s.p.position[0][i], y = s.p.position[1][i];
    if (s.p.is_fluid(i) || x < 0.2 || x > 0.8) continue;
    EXPECT_NEAR(s.p.velocity[0][i], 0.0, 1e-12);
    if (y < -2.0 * dx) {
      EXPECT_EQ(s.p.density[i], rho0) << "wall particle at (" << x << ", " << y << ")";
      ++beyond;
      continue;
    }
    const double expected = rho0 * g * (depth - y);
    EXPECT_NEAR(eos.pressure(s.p.density[i]), expected, 0.001 * expected) << "wall particle at (" << x << ", " << y << ")";
    ++reached;
  }
  EXPECT_EQ(reached, 2 * 30);
  EXPECT_EQ(beyond, 30);
}

TEST(Mdbc, NoSlipReversesTheWaterVelocityFreeSlipOnlyItsNormalPart) {
  for (WallSlip slip : {WallSlip::no_slip, WallSlip::free_slip}) {
    Scene s = make_scene(hydrostatic_density, 3, false);
    for (std::size_t i = 0; i < s.p.size(); ++i)
      if (s.p.is_fluid(i)) s.p.velocity[0][i] = 1.0, s.p.velocity[1][i] = -0.5;
    mdbc_of(s, slip).before_rates(s.p, s.grid, kernel, eos, {0.0, -g}, 1);
    for (std::size_t i = 0; i < s.p.size(); ++i) {
      if (s.p.is_fluid(i) || s.p.position[0][i] < 0.2 || s.p.position[0][i] > 0.8) continue;
      if (s.p.position[1][i] < -2.0 * dx) {  // beyond the water's reach: at rest
        EXPECT_EQ(s.p.velocity[0][i], 0.0);
        EXPECT_EQ(s.p.velocity[1][i], 0.0);
        continue;
      }
      EXPECT_NEAR(s.p.velocity[0][i], slip == WallSlip::no_slip ? -1.0 : 1.0, 1e-12);
      EXPECT_NEAR(s.p.velocity[1][i], 0.5, 1e-12);  // the normal part mirrored in both
    }
  }
}

TEST(Mdbc, WaterInTensionLeavesTheWallAtRestDensityAndAFarWallAtRestToo) {
  Scene s = make_scene([](double) { return 0.99 * rho0; }, 2, true, 1020.0);
  mdbc_of(s, WallSlip::free_slip).before_rates(s.p, s.grid, kernel, eos, {0.0, 0.0}, 1);
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (s.p.is_fluid(i)) continue;
    EXPECT_EQ(s.p.density[i], rho0);  // the fit reads 0.99 rho0; a wall never pulls
    if (s.p.position[1][i] > depth) {
      EXPECT_EQ(s.p.velocity[1][i], 0.0);  // no ghost: at rest
    }
  }
}

TEST(Mdbc, TheExtrapolationIsCappedAtTheDensestWaterPlusTheHydrostaticRise) {
  // Density falling steeply with height, 10 % over 0.1 m: the linear fit at the ghost extrapolates
  // far above anything in the water; the wall takes the cap instead.
  Scene s = make_scene([](double y) { return 1100.0 - 1000.0 * y; }, 3, false);
  mdbc_of(s, WallSlip::free_slip).before_rates(s.p, s.grid, kernel, eos, {0.0, -g}, 1);
  int capped = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    const double x = s.p.position[0][i], y = s.p.position[1][i];
    if (s.p.is_fluid(i) || x < 0.2 || x > 0.8) continue;
    // The densest water within 2h of the ghost (x, -y) is its lowest row, at y = dx/2.
    const double densest = 1100.0 - 1000.0 * 0.5 * dx;
    const double cap = densest + rho0 * g * (2.0 * -y) / (eos.sound_speed * eos.sound_speed);
    EXPECT_LE(s.p.density[i], cap + 1e-9);
    if (y < -dx && y > -2.0 * dx) {
      EXPECT_NEAR(s.p.density[i], cap, 1e-9);  // the fit would give 1100 + 1000 * 1.5 dx = 1130
      ++capped;
    }
  }
  EXPECT_EQ(capped, 30);
}

TEST(Mdbc, ResultsDoNotDependOnTheThreadCount) {
  Scene one = make_scene(hydrostatic_density, 3, true);
  Scene two = make_scene(hydrostatic_density, 3, true);
  for (Scene* s : {&one, &two})
    for (std::size_t i = 0; i < s->p.size(); ++i) s->p.velocity[0][i] = std::sin(7.0 * s->p.position[1][i]);
  mdbc_of(one, WallSlip::no_slip).before_rates(one.p, one.grid, kernel, eos, {0.0, -g}, 1);
  mdbc_of(two, WallSlip::no_slip).before_rates(two.p, two.grid, kernel, eos, {0.0, -g}, 2);
  EXPECT_EQ(one.p.density, two.p.density);
  EXPECT_EQ(one.p.velocity[0], two.p.velocity[0]);
}
