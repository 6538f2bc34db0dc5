// The pair loop (compute_rates: each pair once, forward neighbour lists, bands of cells on several
// threads) against a brute-force reference that sums the pair terms of physics/pair_terms.hpp over
// every ordered pair (i, j), written as directly as the equations: if the forward search missed or
// doubled a pair, or a side of a pair got the wrong sign or mask, the two would differ. Every
// compiled instruction set this CPU runs is checked, in 2D and 3D.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/fluid_sums.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/pair_terms.hpp"
#include "sluice/physics/rates.hpp"
#include "sluice/physics/simd_target.hpp"
#include "sluice/physics/wall_motion.hpp"

using namespace sluice;

namespace {

template <int Dim>
struct Reference {
  std::array<std::vector<double>, Dim> a;
  std::vector<double> drho;
  double max_vij = 0.0, closest = 0.0;
};

template <int Dim>
double distance(const std::array<double, Dim>& r) {
  double r2 = 0.0;
  for (double c : r) r2 += c * c;
  return std::sqrt(r2);
}

// Every ordered pair within the support, fluid i for the momentum, all i for continuity, fluid-fluid
// pairs for density diffusion (as docs/physics.md describes them). Fluid-wall pairs
// have the artificial viscosity alpha * wall_alpha_factor, and each side's P/rho^2 at least
// s.wall_pair_pressure_floor in their pressure term.
template <int Dim, class Kernel>
Reference<Dim> brute_force(const Particles<Dim>& p, const Kernel& kernel, const RateSettings<Dim>& s,
                           const ParticleTerms& t, bool with_ap, double wall_alpha_factor) {
  const std::size_t n = p.size();
  Reference<Dim> ref;
  for (auto& a : ref.a) a.assign(n, 0.0);
  ref.drho.assign(n, 0.0);
  const double support = Kernel::support * s.h;
  double closest = support;
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid_i = p.kind[i] == Kind::fluid;
    for (std::size_t j = 0; j < n; ++j) {
      if (j == i) continue;
      std::array<double, Dim> dx{}, dv{};
      double v_dot_r = 0.0, g_dot_r = 0.0;
      for (int d = 0; d < Dim; ++d) {
        dx[d] = p.position[d][i] - p.position[d][j];
        dv[d] = p.velocity[d][i] - p.velocity[d][j];
        v_dot_r += dv[d] * dx[d];
        g_dot_r += s.gravity[d] * dx[d];
      }
      const double r = distance<Dim>(dx);
      if (r >= support) continue;
      const bool fluid_j = p.kind[j] == Kind::fluid;
      // The pair terms take F = dW/dr / r; here from the kernel's dW/dr, not its gradient_factor.
      const double F = kernel.derivative(r) / r;
      ref.drho[i] += pair::continuity(s.mass, F, v_dot_r);
      if (fluid_i || fluid_j) {
        ref.max_vij = std::max(ref.max_vij, distance<Dim>(dv));
        closest = std::min(closest, r);
      }
      if (!fluid_i) continue;
      if (fluid_j) {
        // The hydrostatic density difference: rho / c^2 g on each side.
        double drho_hydro = 0.0;
        for (int d = 0; d < Dim; ++d) drho_hydro -= 0.5 * (t.rho_gradient[d][i] + t.rho_gradient[d][j]) * dx[d];
        const auto hydro_k = [&](std::size_t k) {
          const double pk = s.eos.pressure(p.density[k]);
          return p.density[k] * p.density[k] / (s.eos.gamma * (pk + s.eos.stiffness()));
        };
        EXPECT_NEAR(drho_hydro, -0.5 * (hydro_k(i) + hydro_k(j)) * g_dot_r, 1e-12 * p.density[i]);
        ref.drho[i] += pair::density_diffusion_flux(s.delta * s.h * s.eos.sound_speed, s.mass, p.density[i],
                                                    p.density[j], drho_hydro, F) /
                       p.density[j];
      }
      const double floor = fluid_j ? -std::numeric_limits<double>::infinity() : s.wall_pair_pressure_floor;
      double along_r = pair::pressure(s.mass, std::max(t.p_over_rho2[i], floor), std::max(t.p_over_rho2[j], floor), F) +
                       pair::artificial_viscosity(fluid_j ? s.alpha : s.alpha * wall_alpha_factor, s.eos.sound_speed,
                                                  s.h, s.mass, v_dot_r, r * r, 0.5 * (p.density[i] + p.density[j]), F);
      if (with_ap) {
        const double f = kernel.value(r) / kernel.value(s.spacing);
        along_r += pair::artificial_pressure(s.mass, t.tension[i], t.tension[j], std::pow(f, s.artificial_pressure_exponent), F);
      }
      const double along_v = pair::laminar_viscosity(s.viscosity, s.mass, 1.0 / (p.density[i] * p.density[i]),
                                                     1.0 / (p.density[j] * p.density[j]), F);
      for (int d = 0; d < Dim; ++d) ref.a[d][i] += along_r * dx[d] + along_v * dv[d];
    }
    if (fluid_i)
      for (int d = 0; d < Dim; ++d) ref.a[d][i] += s.gravity[d];
  }
  ref.closest = closest;
  return ref;
}

// A jittered block of fluid over three layers of wall particles, random velocities and densities:
// 30 x 20 fluid particles in 2D, 10 x 8 x 6 in 3D.
template <int Dim>
Particles<Dim> jittered_block(double dx, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25 * dx, 0.25 * dx), speed(-1.0, 1.0), rho(990.0, 1030.0);
  Particles<Dim> p;
  auto add = [&](const std::array<double, Dim>& x, Kind kind) {
    for (int d = 0; d < Dim; ++d) {
      p.position[d].push_back(x[d] + (kind == Kind::fluid ? jitter(rng) : 0.0));
      p.velocity[d].push_back(kind == Kind::fluid ? speed(rng) : 0.0);
    }
    p.density.push_back(rho(rng));
    p.kind.push_back(kind);
    p.id.push_back(static_cast<std::uint32_t>(p.id.size()));
  };
  const std::array<int, 3> fluid = Dim == 2 ? std::array<int, 3>{30, 20, 1} : std::array<int, 3>{10, 8, 6};
  const int up = Dim - 1;  // the vertical axis
  std::array<int, 3> lo{}, hi{};
  for (int d = 0; d < Dim; ++d) {
    lo[d] = d == up ? -3 : -3;
    hi[d] = d == up ? fluid[d] : fluid[d] + 3;
  }
  std::array<int, 3> c{};
  for (c[2] = Dim > 2 ? lo[2] : 0; c[2] < (Dim > 2 ? hi[2] : 1); ++c[2])
    for (c[1] = lo[1]; c[1] < hi[1]; ++c[1])
      for (c[0] = lo[0]; c[0] < hi[0]; ++c[0]) {
        std::array<double, Dim> x{};
        bool wall = false;
        for (int d = 0; d < Dim; ++d) {
          x[d] = (c[d] + 0.5) * dx;
          wall = wall || (d == up && c[d] < 0);
        }
        bool inside = true;
        for (int d = 0; d < Dim; ++d) inside = inside && c[d] >= 0 && c[d] < fluid[d];
        if (wall) add(x, Kind::wall);
        else if (inside) add(x, Kind::fluid);
      }
  p.resize(p.size());
  return p;
}

template <int Dim>
CellGrid<Dim> block_grid(double cell) {
  Vec<Dim> lower{}, upper{};
  for (int d = 0; d < Dim; ++d) {
    lower[d] = -0.2;
    upper[d] = 0.8;
  }
  return CellGrid<Dim>(lower, upper, cell);
}

// `single`: the pair loop in single precision (domain.pair_precision = "single"), which must match the
// double-precision reference to float round-off: each result within 2e-6 of the largest (floats carry
// 6e-8 relative; a particle's sum has ~50 terms, each about the size of the largest result).
template <int Dim, class Kernel, bool WithAp>
void compare_with_brute_force(int threads, double wall_alpha_factor = 1.0, bool single = false,
                              double wall_pair_floor = -std::numeric_limits<double>::infinity()) {
  const double dx = 0.02;
  Particles<Dim> p = jittered_block<Dim>(dx, 7);
  RateSettings<Dim> s{};
  s.mass = 1000.0 * std::pow(dx, Dim);
  s.h = 1.3 * dx;
  s.viscosity = 1e-3;
  s.alpha = 0.1;
  s.delta = 0.1;
  s.gravity = {};
  s.gravity[Dim - 1] = -9.81;
  s.eos = TaitEos{1000.0, 20.0, 7.0};
  s.artificial_pressure = WithAp ? 0.2 : 0.0;
  s.spacing = dx;
  s.wall_pair_pressure_floor = wall_pair_floor;
  const WallTreatment walls = wall_alpha_factor == 0.0 ? WallTreatment(AdamiWalls{}) : WallTreatment(DynamicWalls{});
  const Kernel kernel(s.h);
  CellGrid<Dim> grid = block_grid<Dim>(2.0 * s.h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  ParticleTerms t;
  t.compute(p, s.eos, s.gravity, 1, s.artificial_pressure);
  const Reference<Dim> ref = brute_force<Dim>(p, kernel, s, t, WithAp, wall_alpha_factor);
  Vec<Dim> middle{};
  for (int d = 0; d < Dim; ++d) middle[d] = 0.3;
  if (single) t.compute(p, s.eos, s.gravity, 1, s.artificial_pressure, true, middle);
  const RateSummary summary = compute_rates<Dim>(p, grid, AnyKernel<Dim>(kernel), walls, s, t, threads);
  const double tolerance = single ? 2e-6 : 1e-12;

  double scale_a = 0.0, scale_rho = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::array<double, Dim> a{};
    for (int d = 0; d < Dim; ++d) a[d] = ref.a[d][i];
    scale_a = std::max(scale_a, distance<Dim>(a));
    scale_rho = std::max(scale_rho, std::abs(ref.drho[i]));
  }
  ASSERT_GT(scale_a, 1.0);
  ASSERT_GT(scale_rho, 1.0);
  std::size_t fluid = 0;
  double worst_a = 0.0, worst_rho = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p.density_rate[i], ref.drho[i], tolerance * scale_rho) << "particle " << p.id[i];
    worst_rho = std::max(worst_rho, std::abs(p.density_rate[i] - ref.drho[i]) / scale_rho);
    if (p.kind[i] != Kind::fluid) continue;
    ++fluid;
    for (int d = 0; d < Dim; ++d) {
      EXPECT_NEAR(p.acceleration[d][i], ref.a[d][i], tolerance * scale_a) << "particle " << p.id[i] << " axis " << d;
      worst_a = std::max(worst_a, std::abs(p.acceleration[d][i] - ref.a[d][i]) / scale_a);
    }
  }
  if (single)
    std::printf("  %dD single precision: largest difference from the reference %.2g (acceleration), %.2g "
                "(density rate) of the largest value\n", Dim, worst_a, worst_rho);
  EXPECT_EQ(fluid, Dim == 2 ? 600u : 480u);
  EXPECT_NEAR(summary.max_relative_speed, ref.max_vij, tolerance * std::max(1.0, ref.max_vij));
  EXPECT_NEAR(summary.min_fluid_distance, ref.closest, tolerance * std::max(1.0, ref.closest));
}

// Runs `check` once with each instruction set this CPU and build have, then returns to the best.
template <class Check>
void on_every_simd_target(Check&& check) {
  const auto targets = available_simd_targets();
  ASSERT_FALSE(targets.empty());
  for (const auto& target : targets) {
    SCOPED_TRACE("SIMD target " + target);
    use_simd_target(target);
    EXPECT_EQ(simd_target(), target);
    check();
  }
  use_simd_target("auto");
  EXPECT_EQ(simd_target(), targets.front());
}

}  // namespace

TEST(Rates, CubicSplineMatchesBruteForceOnOneThread) { compare_with_brute_force<2, CubicSpline<2>, false>(1); }
TEST(Rates, CubicSplineMatchesBruteForceOnTwoThreads) { compare_with_brute_force<2, CubicSpline<2>, false>(2); }
TEST(Rates, WendlandMatchesBruteForce) { compare_with_brute_force<2, WendlandC2<2>, false>(2); }
TEST(Rates, ArtificialPressureMatchesBruteForce) { compare_with_brute_force<2, CubicSpline<2>, true>(2); }
// Adami walls: no artificial viscosity between fluid and wall particles, fluid-fluid pairs keep alpha.
TEST(Rates, WithoutWallArtificialViscosityMatchesBruteForce) {
  compare_with_brute_force<2, CubicSpline<2>, false>(1, 0.0);
  compare_with_brute_force<2, CubicSpline<2>, false>(2, 0.0);
}
// mDBC and Adami walls: no tension between water and wall (the block's densities, 990-1030 kg/m^3,
// give negative pressures on both sides of fluid-wall pairs).
TEST(Rates, WallPairPressureFloorMatchesBruteForce) {
  compare_with_brute_force<2, CubicSpline<2>, false>(2, 1.0, false, 0.0);
  compare_with_brute_force<2, CubicSpline<2>, false>(1, 0.0, false, 0.0);
  compare_with_brute_force<3, WendlandC2<3>, false>(2, 1.0, false, 0.0);
}
TEST(Rates, ThreeDimensionsMatchBruteForce) {
  compare_with_brute_force<3, CubicSpline<3>, false>(2);
  compare_with_brute_force<3, WendlandC2<3>, false>(1, 0.0);
  compare_with_brute_force<3, CubicSpline<3>, true>(2);
}

// Each compiled instruction set (SSE4, AVX2, AVX-512, the portable EMU128, ...) that this CPU runs.
TEST(Rates, EverySimdTargetMatchesBruteForce) {
  on_every_simd_target([] {
    compare_with_brute_force<2, CubicSpline<2>, false>(2);
    compare_with_brute_force<2, WendlandC2<2>, false>(2);
    compare_with_brute_force<2, CubicSpline<2>, true>(2);
    compare_with_brute_force<2, CubicSpline<2>, false>(2, 0.0);
    compare_with_brute_force<3, CubicSpline<3>, false>(2);
    compare_with_brute_force<3, WendlandC2<3>, true>(1, 0.0);
    compare_with_brute_force<2, CubicSpline<2>, false>(2, 1.0, false, 0.0);
    compare_with_brute_force<3, CubicSpline<3>, false>(1, 1.0, false, 0.0);
  });
}

TEST(Rates, SinglePrecisionMatchesBruteForceOnEveryTarget) {
  on_every_simd_target([] {
    compare_with_brute_force<2, CubicSpline<2>, false>(2, 1.0, true);
    compare_with_brute_force<2, WendlandC2<2>, true>(1, 0.0, true);
    compare_with_brute_force<3, CubicSpline<3>, false>(2, 1.0, true);
    compare_with_brute_force<3, WendlandC2<3>, true>(1, 0.0, true);
    compare_with_brute_force<2, CubicSpline<2>, false>(2, 1.0, true, 0.0);
  });
}

// Water and walls all moving at one velocity U (a box carried along, seen from outside): no particle
// approaches another, so the continuity equation gives every density rate zero, and the viscous
// terms vanish. The walls' velocity reaches the continuity equation through their slot of the
// density gradient (ParticleTerms::set_wall_velocity); a wall seen at rest there would compress the
// water above it.
template <int Dim>
void uniform_motion_has_no_density_rate(bool single) {
  const double dx = 0.02;
  Particles<Dim> p = jittered_block<Dim>(dx, 5);
  Vec<Dim> u{};
  u[0] = 0.7;
  u[Dim - 1] = -0.3;
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int d = 0; d < Dim; ++d) p.velocity[d][i] = u[d];
  RateSettings<Dim> s{};
  s.mass = 1000.0 * std::pow(dx, Dim);
  s.h = 1.3 * dx;
  s.viscosity = 1e-3;
  s.alpha = 0.1;
  s.delta = 0.0;  // the density diffusion acts on the jittered densities, not on the motion
  s.eos = TaitEos{1000.0, 20.0, 7.0};
  s.spacing = dx;
  const CubicSpline<Dim> kernel(s.h);
  CellGrid<Dim> grid = block_grid<Dim>(2.0 * s.h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  Vec<Dim> middle{};
  for (int d = 0; d < Dim; ++d) middle[d] = 0.3;
  // The walls as one body translating at u.
  for (std::size_t i = 0; i < p.size(); ++i) p.body[i] = p.is_fluid(i) ? body_id::water : body_id::tank;
  WallMotion<Dim> motion;
  motion.moving = {0, 1};
  motion.state.resize(2);
  motion.state[body_id::tank].velocity = u;
  motion.lower.assign(2, Vec<Dim>{});
  motion.upper.assign(2, Vec<Dim>{});
  for (int d = 0; d < Dim; ++d) {
    motion.lower[body_id::tank][d] = -1.0;
    motion.upper[body_id::tank][d] = 1.0;
  }
  motion.any = true;
  const auto rates = [&](bool walls_move) {
    ParticleTerms t;
    t.compute(p, s.eos, s.gravity, 1, 0.0, single, middle);
    compute_rates<Dim>(p, grid, AnyKernel<Dim>(kernel), WallTreatment(DynamicWalls{}), s, t, 2);
    if (walls_move) add_moving_wall_continuity(p, grid, kernel, s.mass, motion, true, 2);
    return std::pair{p.density_rate, p.acceleration};
  };
  const auto [moving_rate, moving_a] = rates(true);
  // The control: the same walls seen at rest compress the water moving down onto them.
  const auto [resting_walls_rate, resting_walls_a] = rates(false);
  // Everything at rest: the accelerations of the pressures alone, which the uniform motion must leave
  // as they are, bit for bit (its velocity differences are exactly zero).
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int d = 0; d < Dim; ++d) p.velocity[d][i] = 0.0;
  const auto [rest_rate, rest_a] = rates(false);
  // The fluid's and the walls' parts of a pair's velocity difference are summed apart (so that walls
  // at rest cost nothing): zero to round-off of the rates the walls seen at rest give; in single
  // precision to the bound of compare_with_brute_force, 2e-6 of the largest.
  double scale = 0.0;
  for (double r : resting_walls_rate) scale = std::max(scale, std::abs(r));
  const double tolerance = (single ? 2e-6 : 1e-12) * scale;
  std::size_t fluid = 0, compressed = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_LE(std::abs(moving_rate[i]), tolerance) << "particle " << i;
    ASSERT_EQ(rest_rate[i], 0.0) << "particle " << i;
    if (!p.is_fluid(i)) continue;
    ++fluid;
    compressed += resting_walls_rate[i] > 1.0;
    for (int d = 0; d < Dim; ++d) ASSERT_EQ(moving_a[d][i], rest_a[d][i]) << "particle " << i;
  }
  EXPECT_GT(compressed, fluid / 20);
}

TEST(Rates, WaterAndWallsInOneUniformMotionHaveNoDensityRate) {
  on_every_simd_target([] {
    uniform_motion_has_no_density_rate<2>(false);
    uniform_motion_has_no_density_rate<2>(true);
    uniform_motion_has_no_density_rate<3>(false);
    uniform_motion_has_no_density_rate<3>(true);
  });
}

namespace {

// The fluid sums at a point (physics/fluid_sums.hpp, mDBC's ghost nodes) against their definition
// summed over every particle: points inside the block, at its edges, under its floor among the wall
// particles, and beyond it with no fluid in reach; and the tests for a fluid particle within a radius
// of a point and of each wall particle.
template <int Dim, class Kernel>
void compare_fluid_sums_with_brute_force() {
  const double dx = 0.02, h = 1.3 * dx, mass = 1000.0 * std::pow(dx, Dim);
  Particles<Dim> p = jittered_block<Dim>(dx, 11);
  const Kernel kernel(h);
  CellGrid<Dim> grid = block_grid<Dim>(Kernel::support * h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  FluidIndex index, unboxed;
  index.build(p, 2, &grid);
  unboxed.build(p, 1);
  ASSERT_EQ(index.box.size(), grid.cell_count() * 2 * Dim);
  ASSERT_TRUE(unboxed.box.empty());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> across(-0.08, 0.3);
  int with_fluid = 0, without = 0, with_close = 0;
  for (int k = 0; k < 200; ++k) {
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = across(rng);
    if (k == 0) x.fill(0.5);  // far from everything
    const FluidSums<Dim> got = fluid_sums_at<Dim>(p, grid, AnyKernel<Dim>(kernel), mass, index, x);
    LinearFit<Dim> fit;
    Vec<Dim> velocity{};
    int neighbours = 0;
    double densest = 0.0;
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (p.kind[j] != Kind::fluid) continue;
      std::array<double, Dim> y{};
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        y[d] = (p.position[d][j] - x[d]) / h;
        r2 += (p.position[d][j] - x[d]) * (p.position[d][j] - x[d]);
      }
      if (r2 >= Kernel::support * Kernel::support * h * h) continue;
      const double w = kernel.value(std::sqrt(r2)) * mass / p.density[j];
      fit.add(w, y, p.density[j]);
      for (int d = 0; d < Dim; ++d) velocity[d] += w * p.velocity[d][j];
      ++neighbours;
      densest = std::max(densest, p.density[j]);
    }
    (neighbours > 0 ? with_fluid : without) += 1;
    // The test for fluid in reach (mDBC's wall particles), at the support and at 0.6 dx, with the
    // cells' fluid boxes and without.
    const double support2 = Kernel::support * Kernel::support * h * h, close2 = 0.36 * dx * dx;
    EXPECT_EQ(fluid_within<Dim>(p, grid, index, x, support2), neighbours > 0) << "point " << k;
    EXPECT_EQ(fluid_within<Dim>(p, grid, unboxed, x, support2), neighbours > 0) << "point " << k;
    EXPECT_EQ(fluid_within<Dim>(p, grid, unboxed, x, close2), fluid_within<Dim>(p, grid, index, x, close2));
    bool close = false;
    for (std::size_t j = 0; j < p.size(); ++j) {
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) r2 += (p.position[d][j] - x[d]) * (p.position[d][j] - x[d]);
      close = close || (p.kind[j] == Kind::fluid && r2 < close2);
    }
    EXPECT_EQ(fluid_within<Dim>(p, grid, index, x, close2), close) << "point " << k;
    with_close += close;
    EXPECT_EQ(got.neighbours, neighbours) << "point " << k;
    EXPECT_EQ(got.densest, densest) << "point " << k;
    const double scale = 1000.0 * std::max(1.0, fit.weight());
    for (int a = 0; a <= Dim; ++a) {
      EXPECT_NEAR(got.fit.rhs[a], fit.rhs[a], 1e-12 * scale) << "point " << k;
      for (int b = 0; b <= Dim; ++b) EXPECT_NEAR(got.fit.moments[a][b], fit.moments[a][b], 1e-12 * scale);
    }
    for (int d = 0; d < Dim; ++d) EXPECT_NEAR(got.velocity[d], velocity[d], 1e-12 * scale) << "point " << k;
  }
  EXPECT_GT(with_fluid, 30);
  EXPECT_GT(without, 5);
  EXPECT_GT(with_close, 5);
  EXPECT_LT(with_close, with_fluid);
  // Every wall particle's flag (mDBC reads the ghosts of those the water reaches), at the support and
  // at 0.6 dx, against the brute-force search; the fluid particles' entries are left alone.
  for (const double radius2 : {Kernel::support * Kernel::support * h * h, 0.36 * dx * dx}) {
    std::vector<std::uint8_t> reached(p.size(), 7);
    walls_reached<Dim>(p, grid, index, 0, static_cast<std::uint32_t>(grid.cell_count()), radius2, reached.data());
    int in_reach = 0, beyond = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.kind[i] == Kind::fluid) {
        EXPECT_EQ(reached[i], 7);
        continue;
      }
      bool any = false;
      for (std::size_t j = 0; j < p.size() && !any; ++j) {
        double r2 = 0.0;
        for (int d = 0; d < Dim; ++d) r2 += (p.position[d][j] - p.position[d][i]) * (p.position[d][j] - p.position[d][i]);
        any = p.kind[j] == Kind::fluid && r2 < radius2;
      }
      EXPECT_EQ(reached[i], any ? 1 : 0) << "wall particle " << i;
      (any ? in_reach : beyond) += 1;
    }
    if (radius2 > dx * dx) {
      EXPECT_GT(in_reach, 10);
    } else {
      EXPECT_EQ(in_reach, 0);  // the wall particles stand a spacing off the water
    }
    EXPECT_GT(beyond, 10);
  }
}

}  // namespace

TEST(FluidSums, EverySimdTargetMatchesBruteForce) {
  on_every_simd_target([] {
    compare_fluid_sums_with_brute_force<2, CubicSpline<2>>();
    compare_fluid_sums_with_brute_force<2, WendlandC2<2>>();
    compare_fluid_sums_with_brute_force<3, CubicSpline<3>>();
    compare_fluid_sums_with_brute_force<3, WendlandC2<3>>();
  });
}

TEST(SimdTarget, AnUnknownTargetIsAClearError) {
  try {
    use_simd_target("MMX");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("MMX"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(simd_target()), std::string::npos) << e.what();
  }
}

TEST(Rates, ForwardRangesVisitEveryPairOnce) {
  // Every pair of particles in adjacent cells, exactly once, from its first particle.
  Particles<2> p = jittered_block<2>(0.02, 3);
  CellGrid<2> grid = block_grid<2>(0.052);
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
void shepard_against_definition(int threads) {
  const double dx = 0.02, h = 1.3 * dx, mass = 1000.0 * dx * dx;
  Particles<2> p = jittered_block<2>(dx, 11);
  CellGrid<2> grid = block_grid<2>(2.0 * h);
  std::vector<double> scratch;
  grid.bin(p.position);
  p.permute(grid.order(), scratch, false, 1);
  const Kernel kernel(h);
  const std::vector<double> before = p.density;
  std::vector<std::uint8_t> selected(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) selected[i] = i % 3 != 0;
  shepard_filter<2>(p, grid, AnyKernel<2>(kernel), mass, &selected, scratch, threads);
  std::size_t changed = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i) || !selected[i]) {
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
TEST(Shepard, EverySimdTargetMatchesItsDefinition) {
  on_every_simd_target([] {
    shepard_against_definition<CubicSpline<2>>(2);
    shepard_against_definition<WendlandC2<2>>(1);
  });
}
