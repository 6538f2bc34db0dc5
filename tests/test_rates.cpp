// The pair loop (compute_rates: each pair once, forward neighbour lists, bands of cells on several
// threads) against a brute-force reference that sums the pair terms of physics/pair_terms.hpp over
// every ordered pair (i, j), written as directly as the equations: if the forward search missed or
// doubled a pair, or a side of a pair got the wrong sign or mask, the two would differ.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/rates.hpp"

using namespace sluice;

namespace {

struct Reference {
  std::vector<double> ax, ay, drho;
  double max_vij = 0.0, closest = 0.0;
};

// Every ordered pair within the support, fluid i for the momentum, all i for continuity, fluid-fluid
// pairs for density diffusion (as SPEC.md's equations and the README describe them).
template <class Kernel>
Reference brute_force(const Particles<2>& p, const Kernel& kernel, const RateSettings<2>& s, const ParticleTerms& t,
                      bool with_ap) {
  const std::size_t n = p.size();
  Reference ref;
  ref.ax.assign(n, 0.0);
  ref.ay.assign(n, 0.0);
  ref.drho.assign(n, 0.0);
  const double support = Kernel::support * s.h;
  double closest = support;
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid_i = p.kind[i] == Kind::fluid;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      const double dx = p.position[0][i] - p.position[0][j], dy = p.position[1][i] - p.position[1][j];
      const double r = std::hypot(dx, dy);
      if (r >= support) continue;
      const bool fluid_j = p.kind[j] == Kind::fluid;
      const double vx = p.velocity[0][i] - p.velocity[0][j], vy = p.velocity[1][i] - p.velocity[1][j];
      // The pair terms take F = dW/dr / r; here from the kernel's dW/dr, not its gradient_factor.
      const double F = kernel.derivative(r) / r;
      const double v_dot_r = vx * dx + vy * dy;
      ref.drho[i] += pair::continuity(s.mass, F, v_dot_r);
      if (fluid_i || fluid_j) {
        ref.max_vij = std::max(ref.max_vij, std::hypot(vx, vy));
        closest = std::min(closest, r);
      }
      if (!fluid_i) continue;
      if (fluid_j) {
        const double g_dot_r = s.gravity[0] * dx + s.gravity[1] * dy;
        const double drho_hydro = -0.5 * (t.hydro_k[i] + t.hydro_k[j]) * g_dot_r;
        ref.drho[i] += pair::density_diffusion_flux(s.delta * s.h * s.eos.sound_speed, s.mass, p.density[i],
                                                    p.density[j], drho_hydro, F) /
                       p.density[j];
      }
      double along_r = pair::pressure(s.mass, t.p_over_rho2[i], t.p_over_rho2[j], F) +
                       pair::artificial_viscosity(fluid_j ? s.alpha : s.alpha * s.wall_alpha_factor, s.eos.sound_speed, s.h, s.mass, v_dot_r, r * r,
                                                  0.5 * (p.density[i] + p.density[j]), F);
      if (with_ap) {
        const double f = kernel.value(r) / kernel.value(s.spacing);
        along_r += pair::artificial_pressure(s.mass, t.tension[i], t.tension[j], std::pow(f, s.artificial_pressure_exponent), F);
      }
      const double along_v = pair::laminar_viscosity(s.viscosity, s.mass, 1.0 / (p.density[i] * p.density[i]),
                                                     1.0 / (p.density[j] * p.density[j]), F);
      ref.ax[i] += along_r * dx + along_v * vx;
      ref.ay[i] += along_r * dy + along_v * vy;
    }
    if (fluid_i) {
      ref.ax[i] += s.gravity[0];
      ref.ay[i] += s.gravity[1];
    }
  }
  ref.closest = closest;
  return ref;
}

// A jittered block of fluid over three layers of wall particles, random velocities and densities.
Particles<2> jittered_block(double dx, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25 * dx, 0.25 * dx), speed(-1.0, 1.0), rho(990.0, 1030.0);
  Particles<2> p;
  auto add = [&](double x, double y, Kind kind) {
    p.position[0].push_back(x);
    p.position[1].push_back(y);
    p.velocity[0].push_back(kind == Kind::fluid ? speed(rng) : 0.0);
    p.velocity[1].push_back(kind == Kind::fluid ? speed(rng) : 0.0);
    p.density.push_back(rho(rng));
    p.kind.push_back(kind);
    p.id.push_back(static_cast<std::uint32_t>(p.id.size()));
  };
  for (int row = -3; row < 0; ++row)
    for (int col = -3; col < 33; ++col) add((col + 0.5) * dx, (row + 0.5) * dx, Kind::wall);
  for (int row = 0; row < 20; ++row)
    for (int col = 0; col < 30; ++col) add((col + 0.5) * dx + jitter(rng), (row + 0.5) * dx + jitter(rng), Kind::fluid);
  p.resize(p.size());
  return p;
}

template <class Kernel, bool WithAp>
void compare_with_brute_force(int threads, double wall_alpha_factor = 1.0, bool portable = false) {
  const double dx = 0.02;
  Particles<2> p = jittered_block(dx, 7);
  RateSettings<2> s{};
  s.mass = 1000.0 * dx * dx;
  s.h = 1.3 * dx;
  s.viscosity = 1e-3;
  s.alpha = 0.1;
  s.delta = 0.1;
  s.gravity = {0.0, -9.81};
  s.eos = TaitEos{1000.0, 20.0, 7.0};
  s.artificial_pressure = WithAp ? 0.2 : 0.0;
  s.spacing = dx;
  s.wall_alpha_factor = wall_alpha_factor;
  s.portable_pair_loop = portable;
  const Kernel kernel(s.h);
  CellGrid<2> grid({-0.2, -0.2}, {0.8, 0.6}, 2.0 * s.h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  ParticleTerms t;
  t.compute(p, s.eos, 1, s.artificial_pressure);
  const RateSummary summary = compute_rates<2, Kernel, WithAp>(p, grid, kernel, s, t, threads);
  const Reference ref = brute_force(p, kernel, s, t, WithAp);

  double scale_a = 0.0, scale_rho = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    scale_a = std::max(scale_a, std::hypot(ref.ax[i], ref.ay[i]));
    scale_rho = std::max(scale_rho, std::abs(ref.drho[i]));
  }
  ASSERT_GT(scale_a, 1.0);
  ASSERT_GT(scale_rho, 1.0);
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p.density_rate[i], ref.drho[i], 1e-12 * scale_rho) << "particle " << p.id[i];
    if (p.kind[i] != Kind::fluid) continue;
    ++fluid;
    EXPECT_NEAR(p.acceleration[0][i], ref.ax[i], 1e-12 * scale_a) << "particle " << p.id[i];
    EXPECT_NEAR(p.acceleration[1][i], ref.ay[i], 1e-12 * scale_a) << "particle " << p.id[i];
  }
  EXPECT_EQ(fluid, 600u);
  EXPECT_NEAR(summary.max_relative_speed, ref.max_vij, 1e-12);
  EXPECT_NEAR(summary.min_fluid_distance, ref.closest, 1e-12);
}

}  // namespace

TEST(Rates, CubicSplineMatchesBruteForceOnOneThread) { compare_with_brute_force<CubicSpline<2>, false>(1); }
TEST(Rates, CubicSplineMatchesBruteForceOnTwoThreads) { compare_with_brute_force<CubicSpline<2>, false>(2); }
TEST(Rates, WendlandMatchesBruteForce) { compare_with_brute_force<WendlandC2<2>, false>(2); }
TEST(Rates, ArtificialPressureMatchesBruteForce) { compare_with_brute_force<CubicSpline<2>, true>(2); }
// Adami walls: no artificial viscosity between fluid and wall particles, fluid-fluid pairs keep alpha.
TEST(Rates, WithoutWallArtificialViscosityMatchesBruteForce) {
  compare_with_brute_force<CubicSpline<2>, false>(1, 0.0);
  compare_with_brute_force<CubicSpline<2>, false>(2, 0.0);
}

// The portable loop (the only one on machines without AVX-512; the eight-lane loop above otherwise).
TEST(Rates, PortableLoopMatchesBruteForce) {
  compare_with_brute_force<CubicSpline<2>, false>(1, 1.0, true);
  compare_with_brute_force<CubicSpline<2>, false>(2, 1.0, true);
  compare_with_brute_force<WendlandC2<2>, false>(2, 1.0, true);
  compare_with_brute_force<CubicSpline<2>, true>(2, 1.0, true);
  compare_with_brute_force<CubicSpline<2>, false>(2, 0.0, true);
}

TEST(Rates, ForwardRangesVisitEveryPairOnce) {
  // Every pair of particles in adjacent cells, exactly once, from its first particle.
  Particles<2> p = jittered_block(0.02, 3);
  CellGrid<2> grid({-0.2, -0.2}, {0.8, 0.6}, 0.052);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  const std::size_t n = p.size();
  std::vector<int> seen(n * n, 0);
  for (std::uint32_t i = 0; i < n; ++i)
    grid.for_each_forward_range(i, grid.cell_of()[i], [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t j = b; j < e; ++j) {
        ++seen[i * n + j];
        ++seen[j * n + i];
      }
    });
  std::size_t pairs = 0;
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = 0; j < n; ++j) {
      if (i == j) {
        EXPECT_EQ(seen[i * n + j], 0);
        continue;
      }
      const double dx = p.position[0][i] - p.position[0][j], dy = p.position[1][i] - p.position[1][j];
      if (dx * dx + dy * dy < 0.052 * 0.052) {
        EXPECT_EQ(seen[i * n + j], 1) << i << " " << j;
        ++pairs;
      } else {
        EXPECT_LE(seen[i * n + j], 1);
      }
    }
  EXPECT_GT(pairs, 5000u);
}

// The Shepard filter against its definition, rho_i = sum_j m W_ij / sum_j (m / rho_j) W_ij over all j
// within the support including i, summed directly: for the selected fluid particles only, on 1 and 2
// threads, with both kernels.
template <class Kernel>
void shepard_against_definition(int threads, bool portable = false) {
  const double dx = 0.02, h = 1.3 * dx, mass = 1000.0 * dx * dx;
  Particles<2> p = jittered_block(dx, 11);
  CellGrid<2> grid({-0.2, -0.2}, {0.8, 0.6}, 2.0 * h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  const Kernel kernel(h);
  const std::vector<double> before = p.density;
  const auto selected = [](std::size_t i) { return i % 3 != 0; };
  shepard_filter(p, grid, kernel, mass, scratch, threads, selected, portable);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i) || !selected(i)) {
      EXPECT_EQ(p.density[i], before[i]) << "particle " << i << " is not to be filtered";
      continue;
    }
    double weighted_mass = 0.0, weighted_volume = 0.0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      const double r = std::hypot(p.position[0][i] - p.position[0][j], p.position[1][i] - p.position[1][j]);
      weighted_mass += mass * kernel.value(r);
      weighted_volume += mass / before[j] * kernel.value(r);
    }
    EXPECT_NEAR(p.density[i], weighted_mass / weighted_volume, 1e-12 * 1000.0) << "particle " << i;
    changed += std::abs(p.density[i] - before[i]) > 1.0;
  }
  EXPECT_GT(changed, 100u);  // the random densities (990..1030) are smoothed
}

TEST(Shepard, MatchesItsDefinitionCubicOneThread) { shepard_against_definition<CubicSpline<2>>(1); }
TEST(Shepard, MatchesItsDefinitionCubicTwoThreads) { shepard_against_definition<CubicSpline<2>>(2); }
TEST(Shepard, MatchesItsDefinitionWendland) { shepard_against_definition<WendlandC2<2>>(2); }
TEST(Shepard, PortableLoopMatchesItsDefinition) {
  shepard_against_definition<CubicSpline<2>>(2, true);
  shepard_against_definition<WendlandC2<2>>(1, true);
}
