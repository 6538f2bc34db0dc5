// Particle shifting (physics/shifting.hpp): the sums on a regular lattice (div r about Dim inside the
// water, grad C about 0), the free-surface detection (the top rows, not the walls), the direction of
// the shift (back towards the lattice; along the surface only near it), and its independence of the
// thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/shifting.hpp"

using namespace sluice;

namespace {

constexpr double dx = 0.02, h = 1.3 * dx, width = 0.6, depth = 0.4;

// Water 0 <= x <= width, 0 <= y <= depth on the lattice (i + 1/2) dx, moving at 1 m/s along x, on a
// floor of three rows of wall particles and between two walls of three columns; the top is free.
// `move(x, y)` displaces a fluid particle before the sort.
struct Scene {
  Particles<2> p;
  CellGrid<2> grid;
  std::vector<double> fluid;
};

template <class Move>
Scene make_scene(Move move) {
  Scene s;
  const int nx = static_cast<int>(std::lround(width / dx)), ny = static_cast<int>(std::lround(depth / dx));
  for (int i = -3; i < nx + 3; ++i)
    for (int j = -3; j < ny; ++j) {
      const double x = (i + 0.5) * dx, y = (j + 0.5) * dx;
      const bool wall = i < 0 || i >= nx || j < 0;
      std::array<double, 2> at{x, y};
      if (!wall) move(at);
      s.p.add(at, wall ? Kind::wall : Kind::fluid, 1000.0);
    }
  s.p.resize(s.p.size());
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    s.p.id[i] = static_cast<std::uint32_t>(i);
    if (s.p.is_fluid(i)) s.p.velocity[0][i] = 1.0;
  }
  s.grid = CellGrid<2>({-0.2, -0.2}, {width + 0.2, depth + 0.2}, 2.0 * h);
  s.grid.bin(s.p.position);
  std::vector<double> scratch;
  s.p.permute(s.grid.order(), scratch, false, 1);
  for (std::size_t i = 0; i < s.p.size(); ++i) s.fluid.push_back(s.p.is_fluid(i) ? 1.0 : 0.0);
  return s;
}

Scene lattice() {
  return make_scene([](std::array<double, 2>&) {});
}

const ShiftingSums sums{h, dx, dx * dx, 0.2, 4};
const ShiftingSettings settings{2.0, 1.5};

ParticleShifting<2> shift_of(const Scene& s, int threads = 1) {
  ParticleShifting<2> shift;
  shift.compute(s.p, s.grid, AnyKernel<2>(CubicSpline<2>(h)), sums, settings, s.fluid.data(), threads);
  return shift;
}

}  // namespace

TEST(Shifting, OnALatticeDivergenceIsAboutTwoInsideAndTheTopRowIsTheFreeSurface) {
  const Scene s = lattice();
  const ParticleShifting<2> shift = shift_of(s);
  int inside = 0, near = 0, surface = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (!s.p.is_fluid(i)) {
      EXPECT_EQ(shift.zone()[i], SurfaceZone::inside);
      continue;
    }
    const double to_top = depth - s.p.position[1][i], divr = shift.divergence()[i];
    const SurfaceZone zone = shift.zone()[i];
    if (to_top < dx) {
      // The top row: its support is cut in half (div r = 1.28 with h = 1.3 dx).
      EXPECT_LT(divr, settings.surface_threshold);
      EXPECT_EQ(zone, SurfaceZone::surface);
      EXPECT_LT(shift.concentration_gradient(1)[i], 0.0);  // grad C points into the water
      ++surface;
    } else if (to_top - 0.5 * dx < 2.0 * h) {  // within the support of the top row
      EXPECT_EQ(zone, SurfaceZone::near_surface) << "at " << to_top / dx << " dx below the top";
      ++near;
    } else {
      // Inside, next to the walls and the floor too: the wall particles fill the support.
      EXPECT_NEAR(divr, 2.0, 0.03);
      EXPECT_NEAR(shift.concentration_gradient(0)[i], 0.0, 1e-9 / dx);
      EXPECT_NEAR(shift.concentration_gradient(1)[i], 0.0, 1e-9 / dx);
      EXPECT_EQ(zone, SurfaceZone::inside);
      ++inside;
    }
  }
  EXPECT_EQ(surface, 30);
  EXPECT_EQ(near, 2 * 30);
  EXPECT_EQ(inside, 30 * 17);
}

TEST(Shifting, ARegularLatticeIsNotShifted) {
  const Scene s = lattice();
  const ParticleShifting<2> shift = shift_of(s);
  for (std::size_t i = 0; i < s.p.size(); ++i)
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(shift.shift_velocity(d)[i], 0.0, 1e-12) << "particle " << i;
}

TEST(Shifting, ADisplacedParticleIsShiftedBackTowardsItsPlace) {
  // The particle at (0.31, 0.21), in the middle of the water, moved 0.2 dx along +x.
  const auto moved = [](const std::array<double, 2>& x) {
    return std::abs(x[0] - 0.31) < 0.25 * dx && std::abs(x[1] - 0.21) < 0.25 * dx;
  };
  const Scene s = make_scene([&](std::array<double, 2>& x) {
    if (moved(x)) x[0] += 0.2 * dx;
  });
  const ParticleShifting<2> shift = shift_of(s);
  std::size_t k = s.p.size();
  for (std::size_t i = 0; i < s.p.size(); ++i)
    if (s.p.is_fluid(i) && std::abs(s.p.position[0][i] - 0.314) < 1e-9) k = i;
  ASSERT_LT(k, s.p.size());
  const double sx = shift.shift_velocity(0)[k], sy = shift.shift_velocity(1)[k];
  EXPECT_LT(sx, 0.0);
  EXPECT_NEAR(sy, 0.0, 1e-9 * std::abs(sx));
  // Over a step at the CFL time step, the shift is a fraction of the displacement.
  const double dt = 0.2 * h / 30.0;
  EXPECT_LT(std::abs(sx) * dt, 0.2 * dx);
  ParticleShifting<2> copy = shift;
  Particles<2> p = s.p;
  copy.apply(p, dt, 1);
  EXPECT_EQ(p.position[0][k], s.p.position[0][k] + dt * sx);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!p.is_fluid(i)) {
      EXPECT_EQ(p.position[0][i], s.p.position[0][i]);
    }
}

TEST(Shifting, NearTheSurfaceTheShiftIsAlongTheSurface) {
  // Every fluid particle displaced by a fixed pseudo-random amount up to 0.2 dx.
  unsigned state = 12345;
  const auto jitter = [&] {
    state = state * 1103515245u + 12345u;
    return (static_cast<double>((state >> 8) & 0xffff) / 65535.0 - 0.5) * 0.4 * dx;
  };
  const Scene s = make_scene([&](std::array<double, 2>& x) {
    x[0] += jitter();
    x[1] += jitter();
  });
  const ParticleShifting<2> shift = shift_of(s);
  int near = 0, moved_inside = 0;
  for (std::size_t i = 0; i < s.p.size(); ++i) {
    if (!s.p.is_fluid(i)) continue;
    const double sx = shift.shift_velocity(0)[i], sy = shift.shift_velocity(1)[i];
    const double gx = shift.concentration_gradient(0)[i], gy = shift.concentration_gradient(1)[i];
    if (shift.zone()[i] == SurfaceZone::inside) {
      moved_inside += std::hypot(sx, sy) > 0.0;
      continue;
    }
    ++near;
    EXPECT_NEAR(sx * gx + sy * gy, 0.0, 1e-9 * std::hypot(sx, sy) * std::hypot(gx, gy));
  }
  EXPECT_GT(near, 60);
  EXPECT_GT(moved_inside, 400);
}

TEST(Shifting, ResultsDoNotDependOnTheThreadCount) {
  unsigned state = 99;
  const Scene s = make_scene([&](std::array<double, 2>& x) {
    state = state * 1103515245u + 12345u;
    x[0] += (static_cast<double>((state >> 8) & 0xff) / 255.0 - 0.5) * 0.2 * dx;
  });
  const ParticleShifting<2> one = shift_of(s, 1), two = shift_of(s, 2);
  for (int d = 0; d < 2; ++d) EXPECT_EQ(one.shift_velocity(d), two.shift_velocity(d));
  EXPECT_EQ(one.zone(), two.zone());
}

TEST(Shifting, In3DDivergenceIsAboutThreeInsideAndTheTopLayerIsTheFreeSurface) {
  // A block of 12 x 12 x 10 fluid particles on a floor and between walls three layers thick.
  constexpr int n = 12, layers = 10;
  Particles<3> p;
  for (int i = -3; i < n + 3; ++i)
    for (int j = -3; j < n + 3; ++j)
      for (int k = -3; k < layers; ++k) {
        const bool wall = i < 0 || i >= n || j < 0 || j >= n || k < 0;
        p.add({(i + 0.5) * dx, (j + 0.5) * dx, (k + 0.5) * dx}, wall ? Kind::wall : Kind::fluid, 1000.0);
      }
  p.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) p.id[i] = static_cast<std::uint32_t>(i);
  CellGrid<3> grid({-0.1, -0.1, -0.1}, {0.4, 0.4, 0.4}, 2.0 * h);
  grid.bin(p.position);
  std::vector<double> scratch, fluid;
  p.permute(grid.order(), scratch, false, 1);
  for (std::size_t i = 0; i < p.size(); ++i) fluid.push_back(p.is_fluid(i) ? 1.0 : 0.0);
  const ShiftingSums sums3{h, dx, dx * dx * dx, 0.2, 4};
  ParticleShifting<3> shift;
  shift.compute(p, grid, AnyKernel<3>(CubicSpline<3>(h)), sums3, ShiftingSettings{2.0, 2.5}, fluid.data(), 1);
  double top_max = 0.0, below_min = 10.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) continue;
    const double to_top = layers * dx - p.position[2][i], divr = shift.divergence()[i];
    if (to_top < dx) {
      top_max = std::max(top_max, divr);
      EXPECT_EQ(shift.zone()[i], SurfaceZone::surface);
    } else {
      below_min = std::min(below_min, divr);
      EXPECT_NE(shift.zone()[i], SurfaceZone::surface);
      if (to_top - 0.5 * dx >= 2.0 * h) {
        EXPECT_NEAR(divr, 3.0, 0.05);
        EXPECT_EQ(shift.zone()[i], SurfaceZone::inside);
      }
    }
  }
  std::printf("3D lattice: div r of the top layer %.4f, lowest below it %.4f\n", top_max, below_min);
}
