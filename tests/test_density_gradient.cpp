// The renormalised density gradient (physics/density_gradient.hpp) of the full delta-SPH: exact for a
// linear density field wherever the matrix is regular — inside the water, at its free surface and
// beside a wall, whose particles it leaves out — on a jittered lattice, in 2D and 3D; the same as a
// brute-force sum over every pair on every instruction set; independent of the thread count; and
// zero where the neighbours are too few to give a gradient.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/density_gradient.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/simd_target.hpp"

using namespace sluice;

namespace {

constexpr double dx = 0.02, h = 1.3 * dx;

// Water on a lattice jittered by up to dx/4, `cells` per axis, on a floor of three layers of wall
// particles; the top is free. Densities from `rho(x)` (the walls' too: they must not count).
template <int Dim, class Density>
Particles<Dim> block(int cells, Density rho, std::uint32_t seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25 * dx, 0.25 * dx);
  Particles<Dim> p;
  const int up = Dim - 1;
  std::array<int, 3> c{};
  for (c[2] = 0; c[2] < (Dim == 3 ? cells : 1); ++c[2])
    for (c[1] = Dim == 3 ? 0 : -3; c[1] < cells; ++c[1])
      for (c[0] = 0; c[0] < cells; ++c[0]) {
        std::array<int, 3> k = c;
        if constexpr (Dim == 3) k[2] = c[2] - 3;  // the floor's layers under the water in 3D
        const bool wall = k[up] < 0;
        Vec<Dim> x{};
        for (int d = 0; d < Dim; ++d) x[d] = (k[d] + 0.5) * dx + (wall ? 0.0 : jitter(rng));
        p.add(x, wall ? Kind::wall : Kind::fluid, rho(x));
      }
  p.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) p.id[i] = static_cast<std::uint32_t>(i);
  return p;
}

template <int Dim>
CellGrid<Dim> grid_for(Particles<Dim>& p) {
  Vec<Dim> lower{}, upper{};
  for (int d = 0; d < Dim; ++d) {
    lower[d] = -0.2;
    upper[d] = 0.6;
  }
  CellGrid<Dim> grid(lower, upper, 2.0 * h);
  grid.bin(p.position);
  std::vector<double> scratch;
  p.permute(grid.order(), scratch, false, 1);
  return grid;
}

template <int Dim>
std::vector<double> fluid_of(const Particles<Dim>& p) {
  std::vector<double> f(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) f[i] = p.is_fluid(i) ? 1.0 : 0.0;
  return f;
}

// The gradient by the defining sums over every pair (no cells, no vectors), solved the same way.
template <int Dim>
std::array<std::vector<double>, Dim> brute_force(const Particles<Dim>& p, const CubicSpline<Dim>& kernel,
                                                 double mass) {
  std::array<std::vector<double>, Dim> out;
  for (auto& o : out) o.assign(p.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) continue;
    std::array<std::array<double, Dim>, Dim> m{};
    std::array<double, Dim> g{}, x{};
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (j == i || !p.is_fluid(j)) continue;
      std::array<double, Dim> r{};
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        r[d] = p.position[d][i] - p.position[d][j];
        r2 += r[d] * r[d];
      }
      const double dist = std::sqrt(r2);
      if (dist >= 2.0 * h) continue;
      const double fv = kernel.derivative(dist) / dist * mass / p.density[j];
      for (int a = 0; a < Dim; ++a)
        for (int b = a; b < Dim; ++b) m[a][b] -= fv * r[a] * r[b];
      for (int d = 0; d < Dim; ++d) g[d] += (p.density[j] - p.density[i]) * fv * r[d];
    }
    if (SymmetricSolve<Dim>::solve(m, g, x))
      for (int d = 0; d < Dim; ++d) out[d][i] = x[d];
  }
  return out;
}

template <int Dim>
void linear_field_is_exact() {
  Vec<Dim> slope{};
  for (int d = 0; d < Dim; ++d) slope[d] = 30.0 * (d + 1) * (d % 2 == 0 ? 1.0 : -1.0);  // kg/m^4
  const auto rho = [&](const Vec<Dim>& x) {
    double r = 1000.0;
    for (int d = 0; d < Dim; ++d) r += slope[d] * x[d];
    return r;
  };
  Particles<Dim> p = block<Dim>(Dim == 2 ? 16 : 8, rho);
  const CellGrid<Dim> grid = grid_for(p);
  const std::vector<double> fluid = fluid_of(p);
  DensityGradient<Dim> gradient;
  gradient.compute(p, grid, AnyKernel<Dim>(CubicSpline<Dim>(h)), 1000.0 * std::pow(dx, Dim), fluid.data(), 1);
  std::size_t checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) {
      for (int d = 0; d < Dim; ++d) EXPECT_EQ(gradient.gradient()[d][i], 0.0);
      continue;
    }
    // Every fluid particle here has neighbours on at least two sides (corners included).
    for (int d = 0; d < Dim; ++d) EXPECT_NEAR(gradient.gradient()[d][i], slope[d], 1e-9 * std::abs(slope[d])) << i;
    ++checked;
  }
  EXPECT_GT(checked, Dim == 2 ? 250u : 300u);
}

}  // namespace

TEST(RenormalisedDensityGradient, IsExactForALinearFieldAtTheSurfaceAndBesideTheWallIn2D) { linear_field_is_exact<2>(); }

TEST(RenormalisedDensityGradient, IsExactForALinearFieldAtTheSurfaceAndBesideTheWallIn3D) { linear_field_is_exact<3>(); }

TEST(RenormalisedDensityGradient, MatchesTheBruteForceSumOnEveryTargetAndThreadCount) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(990.0, 1030.0);
  Particles<2> p = block<2>(16, [&](const Vec<2>&) { return noise(rng); });
  const CellGrid<2> grid = grid_for(p);
  const std::vector<double> fluid = fluid_of(p);
  const double mass = 1000.0 * dx * dx;
  const auto reference = brute_force<2>(p, CubicSpline<2>(h), mass);
  double largest = 0.0;
  for (const auto& r : reference)
    for (double v : r) largest = std::max(largest, std::abs(v));
  ASSERT_GT(largest, 100.0);
  const auto targets = available_simd_targets();
  ASSERT_FALSE(targets.empty());
  std::vector<double> first;
  for (const auto& target : targets) {
    SCOPED_TRACE("SIMD target " + target);
    use_simd_target(target);
    for (int threads : {1, 2}) {
      DensityGradient<2> gradient;
      gradient.compute(p, grid, AnyKernel<2>(CubicSpline<2>(h)), mass, fluid.data(), threads);
      for (int d = 0; d < 2; ++d)
        for (std::size_t i = 0; i < p.size(); ++i)
          EXPECT_NEAR(gradient.gradient()[d][i], reference[d][i], 1e-11 * largest) << "particle " << i;
      if (threads == 1) first = gradient.gradient()[0];
      else EXPECT_EQ(gradient.gradient()[0], first);  // bit for bit on two threads
    }
  }
  use_simd_target("auto");
}

TEST(RenormalisedDensityGradient, IsZeroWhereTheNeighboursAreTooFew) {
  // Two fluid particles alone (a drop of spray): M has rank one.
  Particles<2> p;
  p.add({0.1, 0.1}, Kind::fluid, 1000.0);
  p.add({0.1 + dx, 0.1}, Kind::fluid, 1010.0);
  p.resize(p.size());
  const CellGrid<2> grid = grid_for(p);
  const std::vector<double> fluid = fluid_of(p);
  DensityGradient<2> gradient;
  gradient.compute(p, grid, AnyKernel<2>(CubicSpline<2>(h)), 1000.0 * dx * dx, fluid.data(), 1);
  for (int d = 0; d < 2; ++d)
    for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(gradient.gradient()[d][i], 0.0);
}
