// The pair loop and the Shepard filter for one instruction set: Highway's foreach_target compiles
// this text once per target (physics/pair_loop_*.cpp, a dimension and precision each), in the
// namespace sluice::HWY_NAMESPACE, with the kernel shapes, the pair terms and the WCSPH pair included
// for that target's vectors.
//
// The traversal: each pair is evaluated once. The particles of a cell share their forward candidates
// (CellGrid::forward_ranges: the rest of their own row of cells and the rows after it), which are
// ranges of consecutive indices. Particle i takes them a vector at a time, loaded contiguously: the
// distances first, and if the vector holds a neighbour, the pair on every lane, the lanes outside the
// support giving exactly nothing. The results for i are summed in registers; those for the candidates
// in a block of the cell's own (CellBlock), added to the particles when the cell is done. (This
// replaced a list of neighbours compressed from the candidates and evaluated with their fields
// gathered: on AMD's Zen 3 the gathers and the scattered additions took more time than the pairs
// the vectors' empty lanes waste.) Threads work on bands of cells (rows in 2D, slabs in 3D): a band's
// pairs reach only into the next band, so all even bands run at once, then all odd ones. Every
// particle therefore receives its contributions in one fixed order — its lower band's, then its own
// band's, in cell order — whatever the number of threads, and the results are the same bit for bit
// on any thread count. The vector sums have an order fixed by the target and the candidate order.
//
// Included once per target (no include guard: a per-target toggle).
#if defined(SLUICE_PHYSICS_PAIR_LOOP_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SLUICE_PHYSICS_PAIR_LOOP_INL_H_
#undef SLUICE_PHYSICS_PAIR_LOOP_INL_H_
#else
#define SLUICE_PHYSICS_PAIR_LOOP_INL_H_
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include <hwy/highway.h>
#include <omp.h>

#include "sluice/core/lanes-inl.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/physics/rate_loops.hpp"

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using simd::Pack;

#include "sluice/physics/kernel_shapes-inl.hpp"
#include "sluice/physics/pair_terms-inl.hpp"
#include "sluice/physics/wcsph_pair-inl.hpp"
#include "sluice/physics/shifting_pair-inl.hpp"
#include "sluice/physics/density_gradient_pair-inl.hpp"

// f(begin, end) for each range of a CellGrid range list. (The loop is here, not a callback through
// CellGrid, which is compiled for the baseline instruction set and could not inline this target's f.)
template <class Ranges, class F>
HWY_INLINE void for_each_range(const Ranges& ranges, F&& f) {
  for (int k = 0; k < ranges.count; ++k) f(ranges.range[k].first, ranges.range[k].second);
}

// The candidates of one cell and what its particles give them. Every particle i of a cell has the
// same forward candidates, except that in its own cell only those after i count: the ranges
// [cell_begin, own_end) and the cell's other forward ranges (CellGrid::ForwardRanges), each taken a
// whole vector at a time from its first index.
//
// In double precision (kDirect) a candidate vector's shares are added straight to the output arrays:
// the band order (for_each_pair) makes this thread the only one writing the particles of these ranges.
// Only the last vector of a range, when the range does not fill it, is summed here (`tail`) and added
// when the cell is done: its lanes past the range's end are other cells' particles, which another
// thread may be writing. In single precision the shares, floats, are summed in a block of the cell's
// own (`to_j`), each candidate at a fixed place, and added to the particles once, when the cell is
// done. Either way no two threads ever write the same place.
template <int Dim, std::size_t Outputs, class R>
struct CellBlock {
  static constexpr bool kDirect = std::is_same_v<R, double>;
  static constexpr int kMaxRanges = (Dim == 3 ? 4 : Dim - 1) + 1;
  static constexpr std::size_t kMaxLanes = HWY_MAX_BYTES / sizeof(R);
  std::array<std::uint32_t, kMaxRanges> begin{}, end{}, offset{}, tail_begin{};
  int ranges = 0;
  std::array<std::vector<R>, Outputs> to_j;  // single precision: in the precision of the pair arithmetic
  // double precision: each range's last, partial vector (from tail_begin), for each output
  alignas(64) std::array<std::array<std::array<R, kMaxLanes>, Outputs>, kMaxRanges> tail;

  // Sets the block to the cell's candidates, with nothing given to them yet.
  template <class Forward>
  void start(std::uint32_t cell_begin, const Forward& forward) {
    const std::size_t N = simd::lanes<R>();
    ranges = 0;
    std::size_t size = 0;
    const auto add = [&](std::uint32_t b, std::uint32_t e) {
      if (e <= b) return;
      begin[ranges] = b;
      end[ranges] = e;
      offset[ranges] = static_cast<std::uint32_t>(size);
      const std::uint32_t whole = (e - b) / static_cast<std::uint32_t>(N) * static_cast<std::uint32_t>(N);
      tail_begin[ranges] = whole == e - b ? e : b + whole;
      if constexpr (kDirect)
        for (auto& t : tail[ranges]) std::fill_n(t.begin(), N, R(0));
      ++ranges;
      size += (e - b + N - 1) / N * N;
    };
    add(cell_begin, forward.own_end);
    for (int k = 0; k < forward.others; ++k) add(forward.other[k].first, forward.other[k].second);
    if constexpr (!kDirect) {
      if (to_j[0].size() < size)
        for (auto& b : to_j) b.resize(2 * size);
      for (auto& b : to_j) std::fill_n(b.begin(), size, R(0));
    }
  }

  // Where output c of the candidate vector of range k starting at j is summed: the output array itself,
  // or (double precision, the range's partial last vector) `tail`; in single precision the block.
  HWY_INLINE R* share(int k, std::size_t c, std::uint32_t j, const std::array<double*, Outputs>& out) {
    if constexpr (kDirect) {
      if (j < tail_begin[k]) return out[c] + j;
      return tail[k][c].data();
    } else {
      return to_j[c].data() + offset[k] + (j - begin[k]);
    }
  }

  // Adds what the cell's particles gave its candidates (and has not added yet) to the output arrays.
  void finish(const std::array<double*, Outputs>& out) const {
    for (int k = 0; k < ranges; ++k) {
      if constexpr (kDirect) {
        const std::uint32_t b = tail_begin[k], n = end[k] - b;
        for (std::size_t c = 0; c < Outputs; ++c)
          for (std::uint32_t q = 0; q < n; ++q) out[c][b + q] += tail[k][c][q];
      } else {
        const std::uint32_t b = begin[k], n = end[k] - b, o = offset[k];
        for (std::size_t c = 0; c < Outputs; ++c) {
          double* __restrict a = out[c] + b;
          const R* __restrict t = to_j[c].data() + o;
          for (std::uint32_t q = 0; q < n; ++q) a[q] += t[q];
        }
      }
    }
  }
};

// The pairs of particle i (in the block's cell, at xi) with the block's candidates: a vector of
// consecutive candidates at a time, loaded contiguously. Lanes outside the support, at or before i in
// its own cell, past a range's end, or coincident with i contribute exactly nothing (their results
// are replaced by zeros); vectors without a neighbour are skipped after the distance test. Adds i's
// sums to the output arrays and the candidates' shares to the block; returns the pair maxima (speed2,
// and the smallest fluid_r2) through `speed2_max` and `r2_min`.
//
// What a pair returns (Pair::Rates<T>): `opposite`, numbers i receives and j receives with the
// opposite sign (a force), then `to_i` and `to_j`, numbers each side receives of its own (a density
// rate); the output arrays are in that order.
//
// For a wall particle i (`WallI`), only the lanes of fluid candidates count: a wall-wall pair gives
// nothing that is used (walls are placed by their bodies' motion, not by rates; the particles of one
// rigid body keep their distances; walls of two bodies do not compress each other's particles; and
// density diffusion acts between fluid particles only), so vectors of wall candidates are skipped,
// and ranges without a fluid particle (`fluid_before`, the fluid particles before each index) are
// passed over without their distances.
template <int Dim, bool WallI, class Pair, class R = typename Pair::Real>
HWY_INLINE void evaluate_pairs(const Pair& shared_pair, std::uint32_t i, const std::array<R, Dim>& xi,
                               const std::array<const R*, Dim>& x, const R* fluid,
                               const std::uint32_t* fluid_before, std::size_t size, double support2,
                               double min_r2, CellBlock<Dim, Pair::kOutputs, R>& block,
                               const std::array<double*, Pair::kOutputs>& out, double& speed2_max, double& r2_min) {
  using V = simd::Lanes<R>;
  constexpr std::size_t A = Pair::kOpposite, S = Pair::kOwn;
  // A copy of its own: the compiler then knows that the stores below do not change the constants of
  // the pair, and keeps them and their products out of the loop. In single precision, with the
  // constants as vectors of floats: out of registers, a constant is then reloaded by a load, not
  // converted from its double again.
  const auto pair = [&] {
    if constexpr (std::is_same_v<R, float>) return shared_pair.template with<V>();
    else return shared_pair;
  }();
  const simd::Tag<R> d;
  const std::size_t N = hn::Lanes(d);
  const auto upper = hn::Set(d, static_cast<R>(support2)), lower = hn::Set(d, static_cast<R>(min_r2));
  const auto si = pair.template side<V>([&](const R* a) { return V(a[i]); });
  std::array<V, A + S> sum;
  sum.fill(0.0);
  V vmax = 0.0, rmin = pair.far_r2;
  for (int k = 0; k < block.ranges; ++k) {
    const std::uint32_t b = block.begin[k], e = block.end[k];
    // In i's own cell (the first range), from the whole vector that holds i + 1.
    std::uint32_t j = b;
    if (k == 0) {
      if (i + 1 >= e) continue;
      j = b + (i + 1 - b) / static_cast<std::uint32_t>(N) * static_cast<std::uint32_t>(N);
    }
    if constexpr (WallI) {
      if (fluid_before[e] == fluid_before[k == 0 ? i + 1 : b]) continue;
    }
    for (; j < e; j += static_cast<std::uint32_t>(N)) {
      const std::size_t skip = (k == 0 && j <= i) ? i + 1 - j : 0;
      const auto valid = hn::AndNot(hn::FirstN(d, skip), hn::FirstN(d, std::min<std::size_t>(N, e - j)));
      std::array<V, Dim> r_ij;
      auto r2 = hn::Zero(d);
      for (int c = 0; c < Dim; ++c) {
        r_ij[c] = V(hn::Set(d, xi[c])) - simd::load_at(x[c], j, size);
        r2 = hn::MulAdd(r_ij[c].v, r_ij[c].v, r2);
      }
      auto near = hn::And(valid, hn::And(hn::Lt(r2, upper), hn::Gt(r2, lower)));
      if constexpr (WallI) near = hn::And(near, hn::Ne(simd::load_at(fluid, j, size).v, hn::Zero(d)));
      const simd::MaskOf<R> hit{near};
      if (hn::AllFalse(d, hit.m)) continue;
      const auto sj = pair.template side<V>([&](const R* a) { return simd::load_at(a, j, size); });
      const auto rates = pair(si, sj, r_ij);
      for (std::size_t c = 0; c < A; ++c) {
        const V f = simd::select(hit, rates.opposite[c], 0.0);
        sum[c] += f;
        R* to = block.share(k, c, j, out);
        simd::store(simd::load(to) - f, to);
      }
      for (std::size_t c = 0; c < S; ++c) {
        sum[A + c] += simd::select(hit, rates.to_i[c], 0.0);
        R* to = block.share(k, A + c, j, out);
        simd::store(simd::load(to) + simd::select(hit, rates.to_j[c], 0.0), to);
      }
      vmax = simd::max(vmax, simd::select(hit, rates.speed2, 0.0));
      rmin = simd::min(rmin, simd::select(hit, rates.fluid_r2, pair.far_r2));
    }
  }
  for (std::size_t c = 0; c < A + S; ++c) out[c][i] += simd::reduce_add(sum[c]);
  speed2_max = std::max(speed2_max, simd::reduce_max(vmax));
  r2_min = std::min(r2_min, simd::reduce_min(rmin));
}

// Every pair within the support of `pair` over the particles at x, once, with the results added to
// the output arrays `out` (zeroed first; Pair::Rates says their order). Wall particles with no fluid
// particle among their forward candidates are skipped (wall-wall pairs are of no use to any pair
// here). Returns the largest speed2 and the smallest fluid_r2 of the pairs through `speed2_max` and
// `r2_min`. Called inside a parallel region, by every thread of it, with `runs` made for that many
// threads.
template <int Dim, class Pair, class R = typename Pair::Real>
HWY_INLINE void for_each_pair(const Pair& pair, const CellGrid<Dim>& grid, const std::array<const R*, Dim>& x,
                              const R* fluid, const std::vector<std::uint32_t>& fluid_before, double support2,
                              double min_r2, const std::array<double*, Pair::kOutputs>& out,
                              std::array<parallel::StealingRuns, 2>& runs, double& speed2_max, double& r2_min) {
  const long n = static_cast<long>(grid.cell_of().size());
  const auto& cell_start = grid.cell_start();
  // This thread's bands, a contiguous run of them (CellGrid::thread_bands), and the particles they
  // hold, which it zeroes: each thread's particles stay in its own core's cache from one pass to the
  // next. Its run's even bands, then its odd ones, are its runs in runs[0] and runs[1]; a thread done
  // with its own takes the others' last bands (parallel::StealingRuns).
  const int t = omp_get_thread_num();
  const auto [band_begin, band_end] = grid.thread_bands(fluid_before, t, omp_get_num_threads());
  const long first = cell_start[grid.band_cells(static_cast<std::size_t>(band_begin)).first];
  const long last = band_end == static_cast<long>(grid.band_count())
                        ? n
                        : cell_start[grid.band_cells(static_cast<std::size_t>(band_end)).first];
  for (long i = first; i < last; ++i)
    for (double* o : out) o[i] = 0.0;
  for (long parity = 0; parity < 2; ++parity)
    runs[parity].set(t, band_begin + ((band_begin + parity) & 1), band_end - 1 - ((band_end - 1 + parity) & 1));
  parallel::barrier();
  CellBlock<Dim, Pair::kOutputs, R> block;
  // Each thread's extremes, combined at the end (max and min do not depend on the order; clang
  // rejects an omp reduction on reference parameters in an orphaned loop). Every thread reads the
  // shared ones before the loops' barriers and writes them after.
  double speed2 = speed2_max, r2 = r2_min;
  for (long parity = 0; parity < 2; ++parity) {
    if (parity == 1) parallel::barrier();
    for (long band = runs[parity].next(t, 2); band >= 0; band = runs[parity].next(t, 2)) {
      const auto [first_cell, last_cell] = grid.band_cells(static_cast<std::size_t>(band));
      for (std::uint32_t cell = first_cell; cell < last_cell; ++cell) {
        const std::uint32_t cell_begin = cell_start[cell], cell_end = cell_start[cell + 1];
        if (cell_begin == cell_end) continue;
        const auto ranges = grid.forward_ranges(cell);
        block.start(cell_begin, ranges);
        for (std::uint32_t i = cell_begin; i < cell_end; ++i) {
          if (fluid[i] == 0.0) {
            bool near_fluid = false;
            for_each_range(ranges.of(i), [&](std::uint32_t begin, std::uint32_t end) {
              near_fluid = near_fluid || (end > begin && fluid_before[end] > fluid_before[begin]);
            });
            if (!near_fluid) continue;
          }
          std::array<R, Dim> xi{};
          for (int d = 0; d < Dim; ++d) xi[d] = x[d][i];
          if (fluid[i] == 0.0)
            evaluate_pairs<Dim, true>(pair, i, xi, x, fluid, fluid_before.data(), static_cast<std::size_t>(n), support2,
                                      min_r2, block, out, speed2, r2);
          else
            evaluate_pairs<Dim, false>(pair, i, xi, x, fluid, fluid_before.data(), static_cast<std::size_t>(n),
                                       support2, min_r2, block, out, speed2, r2);
        }
        block.finish(out);
      }
    }
  }
  parallel::barrier();
#pragma omp critical(sluice_pair_extremes)
  {
    speed2_max = std::max(speed2_max, speed2);
    r2_min = std::min(r2_min, r2);
  }
}

// Fluid particles before each sorted index (for_each_pair's wall-particle test).
// Where prefix_count runs on one thread, the count is this target's own loop: prefix_count is
// compiled for the baseline and would call the test out of line for every particle.
template <class R>
std::vector<std::uint32_t> fluid_counts(const R* fluid, long n, int threads) {
  std::vector<std::uint32_t> before;
  if (threads <= 1 || n < parallel::light_loop_threshold) {
    before.resize(static_cast<std::size_t>(n) + 1);
    std::uint32_t running = 0;
    for (long i = 0; i < n; ++i) {
      before[static_cast<std::size_t>(i)] = running;
      running += fluid[i] != 0.0 ? 1u : 0u;
    }
    before[static_cast<std::size_t>(n)] = running;
    return before;
  }
  parallel::prefix_count(n, threads, before, [fluid](long i) { return fluid[i] != 0.0; });
  return before;
}

// Runs body() on `threads` threads. The region's body is a function of its own, never inlined into
// the function OpenMP outlines for the region: clang compiles that function without this target's
// instruction set, and fails on vector code inlined into it.
template <class Body>
HWY_NOINLINE void team_body(const Body& body) {
  body();
}

// On one thread, and outside any parallel region, body() is called directly: a parallel region of
// one thread still ends in a libgomp barrier, with a futex system call (parallel::barrier).
template <class Body>
void in_parallel(int threads, const Body& body) {
  if (threads <= 1 && !omp_in_parallel()) {
    team_body(body);
    return;
  }
#pragma omp parallel num_threads(threads)
  team_body(body);
}

// Gravity on the fluid, and the largest fluid acceleration and density.
template <int Dim>
HWY_INLINE void add_gravity(Particles<Dim>& p, const Vec<Dim>& g, const double* fluid, double& max_accel2,
                            double& max_rho) {
  const long n = static_cast<long>(p.size());
  // This thread's (see for_each_pair), from the identity of max: another thread may already be
  // combining its own into the shared ones.
  double accel2 = std::numeric_limits<double>::lowest(), rho = std::numeric_limits<double>::lowest();
  // No barrier at the end: the parallel region ends right after (rate_loop).
#pragma omp for schedule(static) nowait
  for (long i = 0; i < n; ++i) {
    rho = std::max(rho, p.density[i]);
    if (fluid[i] == 0.0) continue;
    double a2 = 0.0;
    for (int d = 0; d < Dim; ++d) {
      p.acceleration[d][i] += g[d];
      a2 += p.acceleration[d][i] * p.acceleration[d][i];
    }
    accel2 = std::max(accel2, a2);
  }
#pragma omp critical(sluice_pair_extremes)
  {
    max_accel2 = std::max(max_accel2, accel2);
    max_rho = std::max(max_rho, rho);
  }
}

template <int Dim, class Kernel, class Walls, bool WithArtificialPressure, class R>
RateSummary rate_loop(Particles<Dim>& p, const CellGrid<Dim>& grid, const RateSettings<Dim>& s,
                      const ParticleTerms& t, int threads) {
  const double support2 = Kernel::support * Kernel::support * s.h * s.h;
  // Excludes i = j (and exactly coincident points); in single precision, pairs closer than a
  // millionth of h (whose direction the floats no longer resolve) too.
  const double min_r2 = (std::is_same_v<R, float> ? 1e-12 : 1e-18) * s.h * s.h;
  using Pair = WcsphPair<Dim, Kernel, Walls, WithArtificialPressure, R>;
  const auto pair = Pair::of(p, s, t);

  const PairFields<R> fields = t.template fields<R>(p);
  std::array<const R*, Dim> x{};
  std::array<double*, Pair::kOutputs> out{};
  for (int d = 0; d < Dim; ++d) {
    x[d] = fields.x[d];
    out[d] = p.acceleration[d].data();
  }
  out[Dim] = p.density_rate.data();
  const R* const fluid = fields.fluid;
  const auto fluid_before = fluid_counts(fluid, static_cast<long>(p.size()), threads);

  double max_accel2 = 0.0, max_speed2 = 0.0, max_rho = 0.0, closest2 = support2;
  std::array<parallel::StealingRuns, 2> runs{parallel::StealingRuns(threads), parallel::StealingRuns(threads)};
  in_parallel(threads, [&] {
    for_each_pair<Dim>(pair, grid, x, fluid, fluid_before, support2, min_r2, out, runs, max_speed2, closest2);
    add_gravity<Dim>(p, s.gravity, t.fluid_mask.data(), max_accel2, max_rho);
  });
  return {std::sqrt(max_accel2), std::sqrt(max_speed2), max_rho, std::sqrt(closest2)};
}

// A pair's sums over every pair of particles within its reach (pair.far_r2), in double precision, into
// `out`: for pair sums beside the rates that report nothing else.
template <int Dim, class Pair, std::size_t Outputs>
void sum_pairs(const Particles<Dim>& p, const CellGrid<Dim>& grid, const Pair& pair, double h, const double* fluid,
               const std::array<double*, Outputs>& out, int threads) {
  const double support2 = pair.far_r2, min_r2 = 1e-18 * h * h;
  std::array<const double*, Dim> x{};
  for (int d = 0; d < Dim; ++d) x[d] = p.position[d].data();
  const auto fluid_before = fluid_counts(fluid, static_cast<long>(p.size()), threads);
  double unused_speed2 = 0.0, unused_r2 = support2;
  std::array<parallel::StealingRuns, 2> runs{parallel::StealingRuns(threads), parallel::StealingRuns(threads)};
  in_parallel(threads, [&] {
    for_each_pair<Dim>(pair, grid, x, fluid, fluid_before, support2, min_r2, out, runs, unused_speed2, unused_r2);
  });
}

// The sums of particle shifting (physics/shifting_pair-inl.hpp) into `out`: grad C, grad C^R, div r.
template <int Dim, class Kernel>
void shifting_loop(const Particles<Dim>& p, const CellGrid<Dim>& grid, const ShiftingSums& s, const double* fluid,
                   const std::array<double*, 2 * Dim + 1>& out, int threads) {
  const Kernel kernel(s.h);
  const ShiftingPair<Dim, Kernel> pair{kernel, s.volume, s.tensile, 1.0 / kernel.value(s.spacing), s.exponent,
                                       Kernel::support * Kernel::support * s.h * s.h};
  sum_pairs<Dim>(p, grid, pair, s.h, fluid, out, threads);
}

// The sums of the renormalised density gradient (physics/density_gradient_pair-inl.hpp) into `out`:
// M's upper triangle, then g.
template <int Dim, class Kernel>
void density_gradient_loop(const Particles<Dim>& p, const CellGrid<Dim>& grid, double h, double mass,
                           const double* fluid, const std::array<double*, Dim*(Dim + 1) / 2 + Dim>& out,
                           int threads) {
  const Kernel kernel(h);
  const DensityGradientPair<Dim, Kernel> pair{kernel, mass, Kernel::support * Kernel::support * h * h,
                                              p.density.data(), fluid};
  sum_pairs<Dim>(p, grid, pair, h, fluid, out, threads);
}

template <int Dim, class Kernel>
void shepard_loop(Particles<Dim>& p, const CellGrid<Dim>& grid, double h, double mass,
                  const std::vector<std::uint8_t>* selected, std::vector<double>& out, int threads) {
  const Kernel kernel(h);
  const long n = static_cast<long>(p.size());
  const std::size_t N = simd::lanes();
  const std::size_t size = p.size();
  const auto& cell_of = grid.cell_of();
  out.resize(size);
  // Chunks of particles, each thread taking those of its contiguous share and then the others' last
  // ones (the water may lie in one thread's share), so that the particles' cache lines stay with one
  // core as in the other passes over the particles.
  const long chunk = 256, chunks = (n + chunk - 1) / chunk;
  parallel::StealingRuns runs(threads);
  in_parallel(threads, [&] {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    runs.set(t, chunks * t / team, chunks * (t + 1) / team - 1);
    parallel::barrier();
    for (long c = runs.next(t, 1); c >= 0; c = runs.next(t, 1))
    for (long i = c * chunk, end = std::min(n, (c + 1) * chunk); i < end; ++i) {
      if (!p.is_fluid(static_cast<std::size_t>(i)) || (selected && (*selected)[i] == 0)) {
        out[i] = p.density[i];
        continue;
      }
      // Candidates a vector at a time; those outside the support have W = 0 exactly, and the lanes past
      // the end of a range are placed outside it.
      std::array<Pack, Dim> xi;
      for (int d = 0; d < Dim; ++d) xi[d] = p.position[d][i];
      const double outside = p.position[0][i] + 2.0 * Kernel::support * h;
      Pack mass_sum = 0.0, volume_sum = 0.0;
      for_each_range(grid.neighbor_ranges(cell_of[i]), [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t j = begin; j < end; j += static_cast<std::uint32_t>(N)) {
          const std::size_t lanes = std::min<std::size_t>(N, end - j);
          Pack r2 = 0.0;
          for (int d = 0; d < Dim; ++d) {
            const Pack dx = xi[d] - simd::load_within(p.position[d].data(), j, lanes, size, d == 0 ? outside : 0.0);
            r2 += dx * dx;
          }
          const Pack w = shape::value_inside(kernel, simd::sqrt(r2));
          mass_sum += w;
          volume_sum += w * simd::quotient(Pack(mass), simd::load_within(p.density.data(), j, lanes, size, 1.0));
        }
      });
      out[i] = mass * simd::reduce_add(mass_sum) / simd::reduce_add(volume_sum);
    }
  });
  p.density.swap(out);
}

// r = x_j - point for the candidates j, ..., j + lanes - 1 (the lanes past them at the point itself,
// r = 0) from the coordinate arrays of `size` values, and |r|^2 summed as the pair loop sums it.
template <int Dim>
HWY_INLINE hn::Vec<simd::D> separations(const std::array<const double*, Dim>& x, std::uint32_t j, std::size_t lanes,
                                        std::size_t size, const Vec<Dim>& point, std::array<Pack, Dim>& r) {
  auto r2 = hn::Zero(simd::D());
  for (int c = 0; c < Dim; ++c) {
    r[c] = simd::load_within(x[c], j, lanes, size, point[c]) - Pack(point[c]);
    r2 = hn::MulAdd(r[c].v, r[c].v, r2);
  }
  return r2;
}

// The sums over the fluid around `point` (physics/fluid_sums.hpp): the candidates of the cells next
// to the point's, a vector at a time (ranges without a fluid particle passed
// over), the lanes outside the support, past a range's end or of wall particles weighing nothing.
// Sums in vectors, reduced at the end: the order depends on the target, not on the thread.
template <int Dim, class Kernel>
FluidSums<Dim> fluid_sums_loop(const Particles<Dim>& p, const CellGrid<Dim>& grid, double h, double mass,
                               const FluidIndex& index, const Vec<Dim>& point) {
  constexpr int M = Dim + 1;  // the fit's unknowns: y_0 = 1, y_1..y_Dim = (x_j - point) / h
  const Kernel kernel(h);
  const double support = Kernel::support * h, inv_h = 1.0 / h;
  const simd::D d;
  const std::size_t N = hn::Lanes(d), size = p.size();
  const auto support2 = hn::Set(d, support * support);
  std::array<Pack, M*(M + 1) / 2> moment;  // sum w y_a y_b, a <= b, row by row
  std::array<Pack, M> rhs;                  // sum w rho y_a
  std::array<Pack, Dim> velocity;           // sum w v
  moment.fill(0.0);
  rhs.fill(0.0);
  velocity.fill(0.0);
  Pack densest = 0.0;
  std::size_t neighbours = 0;
  const double* const fluid = index.fluid.data();
  const std::uint32_t* const before = index.before.data();
  const double* const rho_of = p.density.data();
  std::array<const double*, Dim> x, v;
  for (int c = 0; c < Dim; ++c) x[c] = p.position[c].data(), v[c] = p.velocity[c].data();
  // The cells around the point's (the grid's cells are the support wide), as data, looped over here:
  // a callback through CellGrid, compiled for the baseline, could not inline this target's code (nor
  // does GCC inline a lambda with this loop), and the sums would live in memory.
  const auto ranges = grid.neighbor_ranges(grid.cell_at(point));
  for (int range = 0; range < ranges.count; ++range) {
    const auto [begin, end] = ranges.range[range];
    if (before[end] == before[begin]) continue;
    for (std::uint32_t j = begin; j < end; j += static_cast<std::uint32_t>(N)) {
      const std::size_t lanes = std::min<std::size_t>(N, end - j);
      std::array<Pack, Dim> r;
      const auto r2 = separations<Dim>(x, j, lanes, size, point, r);
      // The lanes past the range hold the point itself (r = 0) and fluid = 0: they never count.
      const simd::Mask near{hn::And(hn::Lt(r2, support2),
                                    hn::Ne(simd::load_within(fluid, j, lanes, size, 0.0).v, hn::Zero(d)))};
      if (hn::AllFalse(d, near.m)) continue;
      const Pack rho = simd::load_within(rho_of, j, lanes, size, 1.0);
      const Pack w =
          simd::select(near, shape::value_inside(kernel, simd::sqrt(Pack(r2))) * simd::quotient(Pack(mass), rho), 0.0);
      std::array<Pack, M> y;
      y[0] = 1.0;
      for (int c = 0; c < Dim; ++c) y[c + 1] = r[c] * inv_h;
      for (int a = 0, k = 0; a < M; ++a) {
        const Pack wy = w * y[a];
        rhs[a] += wy * rho;
        for (int b = a; b < M; ++b) moment[k++] += wy * y[b];
      }
      for (int c = 0; c < Dim; ++c) velocity[c] += w * simd::load_within(v[c], j, lanes, size, 0.0);
      densest = simd::max(densest, simd::select(near, rho, 0.0));
      neighbours += hn::CountTrue(d, near.m);
    }
  }
  FluidSums<Dim> s;
  for (int a = 0, k = 0; a < M; ++a) {
    s.fit.rhs[a] = simd::reduce_add(rhs[a]);
    for (int b = a; b < M; ++b, ++k) s.fit.moments[a][b] = s.fit.moments[b][a] = simd::reduce_add(moment[k]);
  }
  for (int c = 0; c < Dim; ++c) s.velocity[c] = simd::reduce_add(velocity[c]);
  s.neighbours = static_cast<int>(neighbours);
  s.densest = simd::reduce_max(densest);
  return s;
}

// The squared distance between the box [lo, hi] and the box `box` (its lower corner, then its upper
// one; lower +inf and upper -inf for an empty box, whose distance is +inf). A point is lo = hi.
template <int Dim>
HWY_INLINE double box_gap2(const double* box, const double* lo, const double* hi) {
  double gap2 = 0.0;
  for (int c = 0; c < Dim; ++c) {
    const double out = std::max({box[c] - hi[c], lo[c] - box[Dim + c], 0.0});
    gap2 += out * out;
  }
  return gap2;
}

// Whether a fluid particle of [begin, end) lies at |x_j - point|^2 < radius2, a vector at a time.
template <int Dim>
HWY_INLINE bool fluid_in_range(const std::array<const double*, Dim>& x, const double* fluid, std::uint32_t begin,
                               std::uint32_t end, std::size_t size, const Vec<Dim>& point, double radius2) {
  const simd::D d;
  const std::size_t N = hn::Lanes(d);
  const auto upper = hn::Set(d, radius2);
  for (std::uint32_t j = begin; j < end; j += static_cast<std::uint32_t>(N)) {
    const std::size_t lanes = std::min<std::size_t>(N, end - j);
    std::array<Pack, Dim> r;
    const auto r2 = separations<Dim>(x, j, lanes, size, point, r);
    // The lanes past the range hold the point itself and fluid = 0: they never count.
    const auto near = hn::And(hn::Lt(r2, upper), hn::Ne(simd::load_within(fluid, j, lanes, size, 0.0).v, hn::Zero(d)));
    if (!hn::AllFalse(d, near)) return true;
  }
  return false;
}

// The boxes are summed without fused multiply-adds, which can round a box's distance above a
// particle's in it by an ulp: their bound is widened by far more than that.
inline double box_reach2(double radius2) { return radius2 * (1.0 + 1e-12); }

// Whether a fluid particle lies closer than sqrt(radius2) to `point` (radius2 at most the square of
// the grid's cell size): the candidates of the cells around the point's whose fluid box is in reach
// (FluidIndex::box, where it was built with the grid), a vector at a time, stopping at the first one
// found.
template <int Dim>
bool fluid_within_loop(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& index,
                       const Vec<Dim>& point, double radius2) {
  const auto& start = grid.cell_start();
  const std::uint32_t* const before = index.before.data();
  std::array<const double*, Dim> x;
  for (int c = 0; c < Dim; ++c) x[c] = p.position[c].data();
  const auto cells = grid.neighbor_cells(grid.cell_at(point));
  for (int row = 0; row < cells.count; ++row) {
    const auto [first, last] = cells.range[row];
    if (before[start[last]] == before[start[first]]) continue;
    for (std::uint32_t cell = first; cell < last; ++cell) {
      if (!index.box.empty() &&
          !(box_gap2<Dim>(index.box.data() + std::size_t{cell} * 2 * Dim, point.data(), point.data()) <
            box_reach2(radius2)))
        continue;
      if (fluid_in_range<Dim>(x, index.fluid.data(), start[cell], start[cell + 1], p.size(), point, radius2)) return true;
    }
  }
  return false;
}

// For each wall particle i of the cells [first_cell, last_cell): reached[i] = 1 if a fluid particle
// lies closer than sqrt(radius2) to it, else 0, as fluid_within says (`index` built with the grid).
// The cells around each cell whose fluid box comes within reach of the box around the cell's wall
// particles are found once for all of them.
template <int Dim>
void walls_reached_loop(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& index,
                        std::uint32_t first_cell, std::uint32_t last_cell, double radius2, std::uint8_t* reached) {
  const auto& start = grid.cell_start();
  const std::uint32_t* const before = index.before.data();
  const double* const fluid = index.fluid.data();
  std::array<const double*, Dim> x;
  for (int c = 0; c < Dim; ++c) x[c] = p.position[c].data();
  const double reach2 = box_reach2(radius2);
  for (std::uint32_t cell = first_cell; cell < last_cell; ++cell) {
    const std::uint32_t b = start[cell], e = start[cell + 1];
    if (before[e] - before[b] == e - b) continue;  // no wall particle
    Vec<Dim> lo, hi;
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
    for (std::uint32_t i = b; i < e; ++i) {
      if (fluid[i] != 0.0) continue;
      for (int c = 0; c < Dim; ++c) lo[c] = std::min(lo[c], x[c][i]), hi[c] = std::max(hi[c], x[c][i]);
    }
    std::array<std::uint32_t, 27> near_cells;
    int near = 0;
    const auto cells = grid.neighbor_cells(cell);
    for (int row = 0; row < cells.count; ++row) {
      const auto [first, last] = cells.range[row];
      for (std::uint32_t k = first; k < last; ++k)
        if (box_gap2<Dim>(index.box.data() + std::size_t{k} * 2 * Dim, lo.data(), hi.data()) < reach2) near_cells[near++] = k;
    }
    for (std::uint32_t i = b; i < e; ++i) {
      if (fluid[i] != 0.0) continue;
      Vec<Dim> xi;
      for (int c = 0; c < Dim; ++c) xi[c] = x[c][i];
      bool found = false;
      for (int n = 0; n < near && !found; ++n) {
        const std::uint32_t k = near_cells[n];
        found = box_gap2<Dim>(index.box.data() + std::size_t{k} * 2 * Dim, xi.data(), xi.data()) < reach2 &&
                fluid_in_range<Dim>(x, fluid, start[k], start[k + 1], p.size(), xi, radius2);
      }
      reached[i] = found ? 1 : 0;
    }
  }
}

// The loops of one kernel and wall pair traits with pairs in precision R, entered in the table; with
// R = double, the kernel's Shepard filter, shifting sums and fluid sums too (those are in double
// precision only).
template <int Dim, class R, std::size_t K, std::size_t W>
void add_rate_loops(DimensionLoops<Dim>& loops) {
  using Kernel = std::variant_alternative_t<K, AnyKernel<Dim>>;
  using Walls = std::variant_alternative_t<W, PairWallTraits>;
  constexpr std::size_t single = std::is_same_v<R, float> ? 1 : 0;
  loops.rates[K][W][0][single] = &rate_loop<Dim, Kernel, Walls, false, R>;
  loops.rates[K][W][1][single] = &rate_loop<Dim, Kernel, Walls, true, R>;
  if constexpr (W == 0 && single == 0) {
    loops.shepard[K] = &shepard_loop<Dim, Kernel>;
    loops.shifting[K] = &shifting_loop<Dim, Kernel>;
    loops.density_gradient[K] = &density_gradient_loop<Dim, Kernel>;
    loops.fluid_sums[K] = &fluid_sums_loop<Dim, Kernel>;
    if constexpr (K == 0) {
      loops.fluid_within = &fluid_within_loop<Dim>;
      loops.walls_reached = &walls_reached_loop<Dim>;
    }
  }
}

template <int Dim, class R, std::size_t K, std::size_t... W>
void add_kernel_loops(DimensionLoops<Dim>& loops, std::index_sequence<W...>) {
  (add_rate_loops<Dim, R, K, W>(loops), ...);
}

// This target's loops of one dimension with pairs in precision R (double or float), entered in its
// table: one per kernel, wall pair traits and artificial-pressure switch, and with R = double the
// Shepard filters and shifting sums. Each dimension and precision is instantiated in a file of its own
// (physics/pair_loop_{2d,3d}_{double,single}.cpp), so that the four compile side by side;
// physics/pair_loop.cpp puts each target's table together.
template <int Dim, class R>
void add_loops(DimensionLoops<Dim>& loops) {
  [&]<std::size_t... K>(std::index_sequence<K...>) {
    (add_kernel_loops<Dim, R, K>(loops, std::make_index_sequence<kPairWallTraits>{}), ...);
  }(std::make_index_sequence<kKernels>{});
}

}  // namespace sluice::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
