// The pair loop, written once: every pair of neighbours found by the cell grid is evaluated once with
// the pair terms of physics/pair_terms.hpp, and its two opposite contributions are added to both
// particles. Threads take alternate bands of cells, so every particle receives its contributions in
// one fixed order and the results do not depend on the number of threads (see compute_rates).
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/simd.hpp"

#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/pair_terms.hpp"

namespace sluice {

template <int Dim>
struct RateSettings {
  double mass;          // particle mass m
  double h;             // smoothing length
  double viscosity;     // mu
  double alpha;         // artificial viscosity
  double delta;         // density diffusion
  Vec<Dim> gravity;
  TaitEos eos;
  double artificial_pressure = 0.0;  // Monaghan (2000) epsilon; 0 = off
  int artificial_pressure_exponent = 4;
  double spacing = 0.0;              // dx, for W(dx) in the artificial pressure
  // Artificial viscosity between a fluid and a wall particle, as a fraction of alpha: 1 with dynamic
  // walls, 0 with Adami walls (free slip). Fluid-fluid pairs always use alpha.
  double wall_alpha_factor = 1.0;
  // Use the portable pair loop even where the AVX-512 one is built (for the tests, which check both).
  bool portable_pair_loop = false;
};

// Per-particle terms computed once per evaluation instead of once per pair.
struct ParticleTerms {
  std::vector<double> p_over_rho2;  // P / rho^2
  std::vector<double> inv_rho;      // 1 / rho
  std::vector<double> hydro_k;      // rho / c^2: d(rho)/d(P) for the hydrostatic density difference
  std::vector<double> fluid_mask;   // 1 for fluid, 0 for wall
  std::vector<double> tension;      // artificial pressure R (only filled when it is on)

  template <int Dim>
  void compute(const Particles<Dim>& p, const TaitEos& eos, int threads, double artificial_pressure = 0.0) {
    const long n = static_cast<long>(p.size());
    for (auto* v : {&p_over_rho2, &inv_rho, &hydro_k, &fluid_mask}) v->resize(static_cast<std::size_t>(n));
    tension.resize(artificial_pressure > 0.0 ? static_cast<std::size_t>(n) : 0);
    // One loop per case, so that each is a straight loop the compiler vectorises: gamma = 7 (x^7 by
    // three multiplications, as TaitEos::pressure does) or any gamma (pow), with or without tension.
    const auto fill = [&](auto power, auto with_tension) {
      const double c0_2 = eos.sound_speed * eos.sound_speed;
      const double stiffness = eos.stiffness(), rho0 = eos.rest_density, gamma = eos.gamma;
      const double* __restrict density = p.density.data();
      const Kind* __restrict kind = p.kind.data();
      double* __restrict pr = p_over_rho2.data();
      double* __restrict ir = inv_rho.data();
      double* __restrict hk = hydro_k.data();
      double* __restrict fm = fluid_mask.data();
      double* __restrict tn = tension.data();
#pragma omp parallel for simd num_threads(threads) schedule(static) if (n >= light_loop_parallel_threshold)
      for (long i = 0; i < n; ++i) {
        const double rho = density[i];
        const double pressure = stiffness * (power(rho / rho0) - 1.0);
        ir[i] = 1.0 / rho;
        pr[i] = pressure * ir[i] * ir[i];
        // c^2 = dP/drho = gamma (P + B) / rho
        const double c2 = gamma * (pressure + stiffness) * ir[i];
        hk[i] = rho / std::max(c2, 1e-12 * c0_2);
        fm[i] = kind[i] == Kind::fluid ? 1.0 : 0.0;
        // Monaghan (2000): eps |P|/rho^2 under tension, 0.01 P/rho^2 under compression.
        if constexpr (decltype(with_tension)::value)
          tn[i] = pressure < 0.0 ? -artificial_pressure * pr[i] : 0.01 * pr[i];
      }
    };
    const auto seventh = [](double x) {
      const double x2 = x * x;
      return x2 * x2 * x2 * x;
    };
    const auto any_power = [g = eos.gamma](double x) { return std::pow(x, g); };
    const bool on = artificial_pressure > 0.0;
    if (eos.gamma == 7.0) {
      if (on) fill(seventh, std::true_type{});
      else fill(seventh, std::false_type{});
    } else {
      if (on) fill(any_power, std::true_type{});
      else fill(any_power, std::false_type{});
    }
  }
};

struct RateSummary {
  double max_acceleration = 0.0;    // over fluid particles, including gravity
  double max_relative_speed = 0.0;  // max |v_ij| over interacting pairs
  double max_density = 0.0;         // over all particles
  double min_fluid_distance = 0.0;  // smallest distance from a fluid particle to any other (clumping)
};

// The neighbours of one particle: indices j and the separations x_i - x_j, gathered once by the
// cell search so that the pair loop reads them contiguously.
template <int Dim>
struct NeighborList {
  std::vector<std::uint32_t> index;
  std::array<std::vector<double>, Dim> separation;
  std::uint32_t count = 0;

  void reserve(std::size_t n) {
    if (index.size() >= n) return;
    index.resize(2 * n);
    for (auto& s : separation) s.resize(2 * n);
  }
};

// Collects the neighbours j != i within the kernel support of particle i (at x_i). Candidates of a
// cell row are consecutive indices; the portable loop is branch-free (every candidate is written, only
// neighbours advance the count), and with AVX-512 eight candidates are tested at once and the
// neighbours compress-stored, which is where explicit SIMD pays: this search is half the pair work.
//
// `for_each_range(f)` calls f(begin, end) for each candidate range, as CellGrid's
// for_each_neighbor_range (all neighbours) or for_each_forward_range (each pair once) do.
template <int Dim, class ForEachRange>
void collect_in_ranges(ForEachRange&& for_each_range, const std::array<double, Dim>& xi,
                       const std::array<const double*, Dim>& x, double support2, double min_r2,
                       NeighborList<Dim>& list) {
  std::uint32_t count = 0;
  for_each_range([&](std::uint32_t begin, std::uint32_t end) {
    if (end <= begin) return;
    list.reserve(count + (end - begin) + 8);
    std::uint32_t* __restrict out = list.index.data();
    std::array<double*, Dim> sep{};
    for (int d = 0; d < Dim; ++d) sep[d] = list.separation[d].data();
    std::uint32_t j = begin;
#if defined(__AVX512F__) && defined(__AVX512VL__)
    if constexpr (Dim == 2) {
      const __m512d xi0 = _mm512_set1_pd(xi[0]), xi1 = _mm512_set1_pd(xi[1]);
      const __m512d upper = _mm512_set1_pd(support2), lower = _mm512_set1_pd(min_r2);
      const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
      for (; j < end; j += 8) {
        const __mmask8 valid = end - j >= 8 ? __mmask8(0xFF) : __mmask8((1u << (end - j)) - 1u);
        const __m512d dx = _mm512_sub_pd(xi0, _mm512_maskz_loadu_pd(valid, x[0] + j));
        const __m512d dy = _mm512_sub_pd(xi1, _mm512_maskz_loadu_pd(valid, x[1] + j));
        const __m512d r2 = _mm512_add_pd(_mm512_mul_pd(dx, dx), _mm512_mul_pd(dy, dy));
        const __mmask8 hit = valid & _mm512_cmp_pd_mask(r2, upper, _CMP_LT_OQ) & _mm512_cmp_pd_mask(r2, lower, _CMP_GT_OQ);
        // Compress in registers and store all eight lanes (the list has room for them): on AMD Zen
        // the compress-to-memory form is microcoded and several times slower.
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + count),
                            _mm256_maskz_compress_epi32(hit, _mm256_add_epi32(_mm256_set1_epi32(static_cast<int>(j)), lane)));
        _mm512_storeu_pd(sep[0] + count, _mm512_maskz_compress_pd(hit, dx));
        _mm512_storeu_pd(sep[1] + count, _mm512_maskz_compress_pd(hit, dy));
        count += static_cast<std::uint32_t>(__builtin_popcount(hit));
      }
      return;
    }
#endif
    for (; j < end; ++j) {
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        const double dx = xi[d] - x[d][j];
        sep[d][count] = dx;
        r2 += dx * dx;
      }
      out[count] = j;
      count += static_cast<std::uint32_t>((r2 < support2) & (r2 > min_r2));
    }
  });
  list.count = count;
}


#if defined(SLUICE_HAVE_AVX512)
// The pair terms of a particle i and its `count` listed neighbours, eight pairs at a time (2D), with
// the same pair:: templates as the portable loop of compute_rates. The last vector is masked: its
// missing lanes get a separation outside the support and zero neighbour data, so their terms are
// exactly zero, and they are neither scattered nor counted in the maxima. The contributions to j are
// added as they are computed (gather, add, scatter): the listed j are distinct, and none is i.
//
// Everything the loop reads is a member, and `run` works on a local copy of *this: the compiler
// cannot tell that the scatters leave the pointers and constants alone when they are reached through
// a reference, and reloaded them from memory on every vector (37 loads in 209 instructions).
template <class Kernel>
struct PairLoopV8 {
  Kernel kernel;
  const double *v0, *v1, *rho, *inv_rho, *p_over_rho2, *hydro_k, *fluid_mask, *tension;
  double *acc0, *acc1, *density_rate;
  double m, c0, h, mu, delta_h_c0, wall_alpha, alpha_gap, g0, g1, inv_w_dx;
  double outside;  // a separation outside the support, for the masked lanes
  int ap_n;        // artificial pressure exponent

  template <bool WithArtificialPressure>
  void run(std::uint32_t i, const std::uint32_t* list, const double* sep0, const double* sep1, std::uint32_t count,
           double& sum0, double& sum1, double& drho, simd::V8& vij2_max, simd::V8& r2_min) const {
    using simd::Mask8;
    using simd::V8;
    const PairLoopV8 c = *this;
    const V8 vi0 = c.v0[i], vi1 = c.v1[i];
    const V8 rho_i = c.rho[i], inv_rho_i = c.inv_rho[i], pr_i = c.p_over_rho2[i];
    const V8 ir2_i = c.inv_rho[i] * c.inv_rho[i], k_i = c.hydro_k[i], fluid_i = c.fluid_mask[i];
    const V8 tension_i = WithArtificialPressure ? c.tension[i] : 0.0;
    V8 s0 = 0.0, s1 = 0.0, sr = 0.0;
    V8 vmax = vij2_max, rmin = r2_min;
    for (std::uint32_t k = 0; k < count; k += 8) {
      const Mask8 valid{count - k >= 8 ? __mmask8(0xFF) : __mmask8((1u << (count - k)) - 1u)};
      const __m256i j = _mm256_maskz_loadu_epi32(valid.m, list + k);
      const V8 dx0 = V8::load(valid, sep0 + k, c.outside), dx1 = V8::load(valid, sep1 + k, 0.0);
      const V8 rho_j = V8::gather(valid, j, c.rho), inv_rho_j = V8::gather(valid, j, c.inv_rho);
      const V8 fluid_j = V8::gather(valid, j, c.fluid_mask);
      const V8 vij0 = vi0 - V8::gather(valid, j, c.v0), vij1 = vi1 - V8::gather(valid, j, c.v1);
      const V8 r2 = dx0 * dx0 + dx1 * dx1;
      const V8 v_dot_r = vij0 * dx0 + vij1 * dx1;
      const V8 g_dot_r = c.g0 * dx0 + c.g1 * dx1;
      const V8 inv_r = simd::inverse_sqrt(r2);
      const V8 r = r2 * inv_r;
      const V8 F = c.kernel.gradient_factor(r, inv_r);
      const V8 both_fluid = fluid_i * fluid_j;
      const V8 alpha_ij = c.wall_alpha + both_fluid * c.alpha_gap;
      V8 along_r = pair::pressure(c.m, pr_i, V8::gather(valid, j, c.p_over_rho2), F) +
                   pair::artificial_viscosity(alpha_ij, c.c0, c.h, c.m, v_dot_r, r2, 0.5 * (rho_i + rho_j), F);
      if constexpr (WithArtificialPressure) {
        const V8 f = c.kernel.value_inside(r) * c.inv_w_dx;
        V8 f_n = 1.0;
        for (int e = 0; e < c.ap_n; ++e) f_n = f_n * f;
        along_r += pair::artificial_pressure(c.m, tension_i, V8::gather(valid, j, c.tension), f_n, F);
      }
      const V8 along_v = pair::laminar_viscosity(c.mu, c.m, ir2_i, inv_rho_j * inv_rho_j, F);
      const V8 f0 = along_r * dx0 + along_v * vij0;
      const V8 f1 = along_r * dx1 + along_v * vij1;
      const V8 drho_hydro = -0.5 * (k_i + V8::gather(valid, j, c.hydro_k)) * g_dot_r;
      const V8 continuity = pair::continuity(c.m, F, v_dot_r);
      const V8 flux = both_fluid * pair::density_diffusion_flux(c.delta_h_c0, c.m, rho_i, rho_j, drho_hydro, F);
      s0 += f0;
      s1 += f1;
      sr += continuity + flux * inv_rho_j;
      (V8::gather(valid, j, c.acc0) - f0).scatter(valid, j, c.acc0);
      (V8::gather(valid, j, c.acc1) - f1).scatter(valid, j, c.acc1);
      (V8::gather(valid, j, c.density_rate) + (continuity - flux * inv_rho_i)).scatter(valid, j, c.density_rate);
      const __mmask8 with_fluid = valid.m & (simd::max(fluid_i, fluid_j) != 0.0).m;
      vmax.v = _mm512_mask_max_pd(vmax.v, with_fluid, vmax.v, (vij0 * vij0 + vij1 * vij1).v);
      rmin.v = _mm512_mask_min_pd(rmin.v, with_fluid, rmin.v, r2.v);
    }
    vij2_max = vmax;
    r2_min = rmin;
    sum0 = simd::reduce_add(s0);
    sum1 = simd::reduce_add(s1);
    drho = simd::reduce_add(sr);
  }
};
#endif

// Fills p.acceleration (fluid particles; wall entries are scratch) and p.density_rate (all particles).
//
// Each pair is evaluated once (Newton's third law): particle i collects its forward neighbours from
// the cell grid (CellGrid::forward_ranges, computed once per cell), the pair terms are summed into i,
// and the opposite contributions are added to the neighbours j. In 2D with AVX-512 this is
// PairLoopV8, eight pairs at a time; otherwise a portable loop written branch-free so that the
// compiler vectorises it, whose contributions to j are added after it. Threads work on bands of cells
// (rows in 2D): a band's pairs reach only into the next band, so all even bands run at once, then all
// odd ones. Every particle therefore receives its contributions in one fixed order — its lower band's,
// then its own band's, in index order — whatever the number of threads, and the results are the same
// bit for bit on any thread count. The vectorised sums have an order fixed by the binary and the
// neighbour order, never by the thread count.
//
// The portable loop pads its neighbour lists to a multiple of this many entries (whole SIMD vectors).
inline constexpr std::uint32_t kLanes = 16;

template <int Dim, class Kernel, bool WithArtificialPressure = false>
RateSummary compute_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel,
                          const RateSettings<Dim>& s, const ParticleTerms& t, int threads) {
  static_assert(Dim >= 1 && Dim <= 3);
  const double inv_w_dx = WithArtificialPressure ? 1.0 / kernel.value(s.spacing) : 0.0;
  const int ap_n = s.artificial_pressure_exponent;
  const long n = static_cast<long>(p.size());
  const double support2 = Kernel::support * Kernel::support * s.h * s.h;
  const double min_r2 = 1e-18 * s.h * s.h;  // excludes i = j (and exactly coincident points)
  const double m = s.mass;
  const double c0 = s.eos.sound_speed;
  const double h = s.h;
  const double alpha = s.alpha;
  const double wall_alpha = s.alpha * s.wall_alpha_factor;
  const double alpha_gap = alpha - wall_alpha;  // 0 with wall_alpha_factor = 1: alpha_ij is alpha exactly
  const double mu = s.viscosity;
  const double delta_h_c0 = s.delta * s.h * c0;
  const auto& cell_start = grid.cell_start();
  const double g0 = s.gravity[0];
  const double g1 = Dim > 1 ? s.gravity[Dim > 1 ? 1 : 0] : 0.0;
  const double g2 = Dim > 2 ? s.gravity[Dim > 2 ? 2 : 0] : 0.0;

  std::array<const double*, Dim> x{};
  for (int d = 0; d < Dim; ++d) x[d] = p.position[d].data();
  // Component pointers; unused dimensions point at x (or at acc0), and are never read or written.
  const double* __restrict v0 = p.velocity[0].data();
  const double* __restrict v1 = p.velocity[Dim > 1 ? 1 : 0].data();
  const double* __restrict v2 = p.velocity[Dim > 2 ? 2 : 0].data();
  const double* __restrict rho = p.density.data();
  const double* __restrict p_over_rho2 = t.p_over_rho2.data();
  const double* __restrict inv_rho = t.inv_rho.data();
  const double* __restrict hydro_k = t.hydro_k.data();
  const double* __restrict fluid_mask = t.fluid_mask.data();
  const double* __restrict tension = t.tension.data();
  double* const acc0 = p.acceleration[0].data();
  double* const acc1 = p.acceleration[Dim > 1 ? 1 : 0].data();
  double* const acc2 = p.acceleration[Dim > 2 ? 2 : 0].data();
  double* const density_rate = p.density_rate.data();

  double max_accel2 = 0.0;
  double max_vij2 = 0.0;
  double max_rho = 0.0;
  double closest2 = support2;

  // Fluid particles before each sorted index: a wall particle with no fluid among its forward
  // candidates has only wall-wall pairs there (v_ij = 0, no diffusion, wall accelerations unused) and
  // is skipped.
  std::vector<std::uint32_t> fluid_before(static_cast<std::size_t>(n) + 1, 0);
  for (long i = 0; i < n; ++i) fluid_before[i + 1] = fluid_before[i] + (fluid_mask[i] != 0.0);
  const long bands = static_cast<long>(grid.band_count());

#pragma omp parallel num_threads(threads)
  {
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      acc0[i] = 0.0;
      if constexpr (Dim > 1) acc1[i] = 0.0;
      if constexpr (Dim > 2) acc2[i] = 0.0;
      density_rate[i] = 0.0;
    }
    NeighborList<Dim> neighbors;
    neighbors.reserve(512);
    std::vector<double> to_j0, to_j1, to_j2, to_j_rho;  // the contributions to the neighbours j

#if defined(SLUICE_HAVE_AVX512)
    simd::V8 vij2_max_v = 0.0, r2_min_v = support2;  // over this thread's pairs with a fluid particle
    const PairLoopV8<Kernel> pair_loop{kernel, v0, v1, rho, inv_rho, p_over_rho2, hydro_k, fluid_mask, tension,
                                       acc0, acc1, density_rate, m, c0, h, mu, delta_h_c0, wall_alpha, alpha_gap,
                                       g0, g1, inv_w_dx, 1.5 * Kernel::support * h, ap_n};
#endif

    for (long parity = 0; parity < 2; ++parity) {
#pragma omp for schedule(dynamic, 1) reduction(max : max_vij2) reduction(min : closest2)
      for (long band = parity; band < bands; band += 2) {
        const auto [first_cell, last_cell] = grid.band_cells(static_cast<std::size_t>(band));
        for (std::uint32_t cell = first_cell; cell < last_cell; ++cell) {
          const std::uint32_t cell_begin = cell_start[cell], cell_end = cell_start[cell + 1];
          if (cell_begin == cell_end) continue;
          const auto ranges = grid.forward_ranges(cell);
          for (std::uint32_t i = cell_begin; i < cell_end; ++i) {
            const auto forward = [&](auto&& f) { CellGrid<Dim>::for_each_forward_range(i, ranges, f); };
            const double fluid_i = fluid_mask[i];
            if (fluid_i == 0.0) {
              bool near_fluid = false;
              forward([&](std::uint32_t begin, std::uint32_t end) {
                near_fluid = near_fluid || (end > begin && fluid_before[end] > fluid_before[begin]);
              });
              if (!near_fluid) continue;
            }
            std::array<double, Dim> xi{};
            for (int d = 0; d < Dim; ++d) xi[d] = x[d][i];
            collect_in_ranges<Dim>(forward, xi, x, support2, min_r2, neighbors);
            const std::uint32_t count = neighbors.count;
            if (count == 0) continue;
#if defined(SLUICE_HAVE_AVX512)
            if constexpr (Dim == 2) {
              if (!s.portable_pair_loop) {
                double sum0 = 0.0, sum1 = 0.0, drho = 0.0;
                pair_loop.template run<WithArtificialPressure>(i, neighbors.index.data(),
                                                             neighbors.separation[0].data(),
                                                             neighbors.separation[1].data(), count, sum0, sum1,
                                                             drho, vij2_max_v, r2_min_v);
                acc0[i] += sum0;
                acc1[i] += sum1;
                density_rate[i] += drho;
                continue;
              }
            }
#endif
            // Pad the list to whole SIMD vectors with entries outside the support (j = i at a distance
            // 1.5 support), whose terms are exactly zero: the pair loop then runs only full vectors
            // instead of a long scalar remainder on these short (half) lists.
            const std::uint32_t padded = (count + kLanes - 1) / kLanes * kLanes;
            neighbors.reserve(padded);
            for (std::uint32_t k = count; k < padded; ++k) {
              neighbors.index[k] = i;
              neighbors.separation[0][k] = 1.5 * Kernel::support * h;
              for (int d = 1; d < Dim; ++d) neighbors.separation[d][k] = 0.0;
            }
            if (to_j0.size() < padded) {
              for (auto* b : {&to_j0, &to_j1, &to_j2, &to_j_rho}) b->resize(2 * padded);
            }
            const std::uint32_t* __restrict list = neighbors.index.data();
            const double* __restrict sep0 = neighbors.separation[0].data();
            const double* __restrict sep1 = neighbors.separation[Dim > 1 ? 1 : 0].data();
            const double* __restrict sep2 = neighbors.separation[Dim > 2 ? 2 : 0].data();
            double* __restrict out0 = to_j0.data();
            double* __restrict out1 = to_j1.data();
            double* __restrict out2 = to_j2.data();
            double* __restrict out_rho = to_j_rho.data();

            const double vi0 = v0[i], vi1 = Dim > 1 ? v1[i] : 0.0, vi2 = Dim > 2 ? v2[i] : 0.0;
            const double rho_i = rho[i];
            const double inv_rho_i = inv_rho[i];
            const double pr_i = p_over_rho2[i];
            const double ir2_i = inv_rho_i * inv_rho_i;
            const double k_i = hydro_k[i];
            const double tension_i = WithArtificialPressure ? tension[i] : 0.0;
            double sum0 = 0.0, sum1 = 0.0, sum2 = 0.0, drho = 0.0;
            double vij2_max = 0.0;
            double r2_min = support2;
#pragma omp simd reduction(+ : sum0, sum1, sum2, drho) reduction(max : vij2_max) reduction(min : r2_min)
            for (std::uint32_t k = 0; k < padded; ++k) {
              const std::uint32_t j = list[k];
              const double dx0 = sep0[k];
              const double dx1 = Dim > 1 ? sep1[k] : 0.0;
              const double dx2 = Dim > 2 ? sep2[k] : 0.0;
              const double vij0 = vi0 - v0[j];
              const double vij1 = Dim > 1 ? vi1 - v1[j] : 0.0;
              const double vij2 = Dim > 2 ? vi2 - v2[j] : 0.0;
              const double r2 = dx0 * dx0 + dx1 * dx1 + dx2 * dx2;
              const double v_dot_r = vij0 * dx0 + vij1 * dx1 + vij2 * dx2;
              const double g_dot_r = g0 * dx0 + g1 * dx1 + g2 * dx2;
              const double r = std::sqrt(r2);
              const double F = kernel.gradient_factor(r, 1.0 / r);
              const double rho_j = rho[j];
              const double inv_rho_j = inv_rho[j];
              const double fluid_j = fluid_mask[j];
              const double both_fluid = fluid_i * fluid_j;
              const double alpha_ij = wall_alpha + both_fluid * alpha_gap;

              double along_r = pair::pressure(m, pr_i, p_over_rho2[j], F) +
                               pair::artificial_viscosity(alpha_ij, c0, h, m, v_dot_r, r2, 0.5 * (rho_i + rho_j), F);
              if constexpr (WithArtificialPressure) {
                const double f = kernel.value_inside(r) * inv_w_dx;
                double f_n = 1.0;
                for (int e = 0; e < ap_n; ++e) f_n *= f;
                along_r += pair::artificial_pressure(m, tension_i, tension[j], f_n, F);
              }
              const double along_v = pair::laminar_viscosity(mu, m, ir2_i, inv_rho_j * inv_rho_j, F);
              // Both sides of the pair: the forces are opposite, the continuity terms equal, and density
              // diffusion acts between fluid particles only.
              const double f0 = along_r * dx0 + along_v * vij0;
              const double f1 = along_r * dx1 + along_v * vij1;
              const double f2 = along_r * dx2 + along_v * vij2;
              const double drho_hydro = -0.5 * (k_i + hydro_k[j]) * g_dot_r;  // rho_j^H - rho_i^H
              const double continuity = pair::continuity(m, F, v_dot_r);
              const double flux =
                  both_fluid * pair::density_diffusion_flux(delta_h_c0, m, rho_i, rho_j, drho_hydro, F);
              sum0 += f0;
              sum1 += f1;
              sum2 += f2;
              drho += continuity + flux * inv_rho_j;
              out0[k] = -f0;
              out1[k] = -f1;
              out2[k] = -f2;
              out_rho[k] = continuity - flux * inv_rho_i;
              // Over the pairs with a fluid particle: the relative speed (time step) and the closest
              // approach (clumping).
              const double any_fluid = std::max(fluid_i, fluid_j);
              vij2_max = std::max(vij2_max, any_fluid * (vij0 * vij0 + vij1 * vij1 + vij2 * vij2));
              r2_min = std::min(r2_min, any_fluid != 0.0 ? r2 : support2);
            }
            // No two entries of the list are the same particle, so these updates are independent.
#pragma omp simd
            for (std::uint32_t k = 0; k < count; ++k) {
              const std::uint32_t j = list[k];
              acc0[j] += out0[k];
              if constexpr (Dim > 1) acc1[j] += out1[k];
              if constexpr (Dim > 2) acc2[j] += out2[k];
              density_rate[j] += out_rho[k];
            }
            acc0[i] += sum0;
            if constexpr (Dim > 1) acc1[i] += sum1;
            if constexpr (Dim > 2) acc2[i] += sum2;
            density_rate[i] += drho;
            max_vij2 = std::max(max_vij2, vij2_max);
            closest2 = std::min(closest2, r2_min);
          }
        }
#if defined(SLUICE_HAVE_AVX512)
        max_vij2 = std::max(max_vij2, simd::reduce_max(vij2_max_v));
        closest2 = std::min(closest2, simd::reduce_min(r2_min_v));
#endif
      }
    }

    // Gravity, and the largest fluid acceleration and density.
#pragma omp for schedule(static) reduction(max : max_accel2, max_rho)
    for (long i = 0; i < n; ++i) {
      max_rho = std::max(max_rho, rho[i]);
      if (fluid_mask[i] == 0.0) continue;
      acc0[i] += g0;
      if constexpr (Dim > 1) acc1[i] += g1;
      if constexpr (Dim > 2) acc2[i] += g2;
      const double a2 = acc0[i] * acc0[i] + (Dim > 1 ? acc1[i] * acc1[i] : 0.0) + (Dim > 2 ? acc2[i] * acc2[i] : 0.0);
      max_accel2 = std::max(max_accel2, a2);
    }
  }
  return {std::sqrt(max_accel2), std::sqrt(max_vij2), max_rho, std::sqrt(closest2)};
}

// Shepard density filter (sum includes i = j): rho_i = sum_j m W_ij / sum_j (m/rho_j) W_ij, applied
// to fluid particles for which `select(i)` is true. `out` is scratch of size n.
template <int Dim, class Kernel, class Select>
void shepard_filter(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, double mass,
                    std::vector<double>& out, int threads, Select select, [[maybe_unused]] bool portable = false) {
  const long n = static_cast<long>(p.size());
  const double support2 = Kernel::support * Kernel::support * kernel.h * kernel.h;
  const auto& cell_of = grid.cell_of();
  out.assign(p.density.begin(), p.density.end());
#pragma omp parallel for schedule(dynamic, 512) num_threads(threads)
  for (long i = 0; i < n; ++i) {
    if (!p.is_fluid(static_cast<std::size_t>(i)) || !select(static_cast<std::size_t>(i))) continue;
    double weighted_mass = 0.0, weighted_volume = 0.0;
#if defined(SLUICE_HAVE_AVX512)
    if constexpr (Dim == 2) {
      if (!portable) {
        // Eight candidates at a time; those outside the support have W = 0 exactly (q is clamped at 2),
        // and the lanes past the end of a range are placed outside it.
        using simd::Mask8;
        using simd::V8;
        const double x_i = p.position[0][i];
        const V8 xi = x_i, yi = p.position[1][i];
        const double outside = x_i + 2.0 * Kernel::support * kernel.h;  // a position outside i's support
        V8 mass_sum = 0.0, volume_sum = 0.0;
        grid.for_each_neighbor_range(cell_of[i], [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t j = begin; j < end; j += 8) {
            const Mask8 valid{end - j >= 8 ? __mmask8(0xFF) : __mmask8((1u << (end - j)) - 1u)};
            const V8 dx = xi - V8::load(valid, p.position[0].data() + j, outside);
            const V8 dy = yi - V8::load(valid, p.position[1].data() + j, 0.0);
            const V8 w = kernel.value_inside(simd::sqrt(dx * dx + dy * dy));
            mass_sum += w;
            volume_sum += w * simd::quotient(mass, V8::load(valid, p.density.data() + j, 1.0));
          }
        });
        out[i] = mass * simd::reduce_add(mass_sum) / simd::reduce_add(volume_sum);
        continue;
      }
    }
#endif
    grid.for_each_neighbor_range(cell_of[i], [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t j = begin; j < end; ++j) {
        double r2 = 0.0;
        for (int d = 0; d < Dim; ++d) {
          const double dx = p.position[d][i] - p.position[d][j];
          r2 += dx * dx;
        }
        if (r2 >= support2) continue;
        const double w = kernel.value(std::sqrt(r2));
        weighted_mass += mass * w;
        weighted_volume += mass / p.density[j] * w;
      }
    });
    out[i] = weighted_mass / weighted_volume;
  }
  p.density.swap(out);
}

}  // namespace sluice
