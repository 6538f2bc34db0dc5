// The pair loop and the Shepard filter for one instruction set: Highway's foreach_target compiles
// this text once per target (physics/pair_loop.cpp), in the namespace sluice::HWY_NAMESPACE, with the
// kernel shapes, the pair terms and the WCSPH pair included for that target's vectors.
//
// The traversal: each pair is evaluated once. Particle i collects its forward neighbours from the
// cell grid (CellGrid::forward_ranges), a vector of candidates at a time, compressing those within the
// support into a list of indices and separations; the list is padded to whole vectors with entries
// outside the support (whose terms are exactly zero), the pair is evaluated a vector of neighbours at a
// time with their fields gathered, the results for i are summed and those for the j stored and then
// added to them. Threads work on bands of cells (rows in 2D, slabs in 3D): a band's pairs reach only
// into the next band, so all even bands run at once, then all odd ones. Every particle therefore
// receives its contributions in one fixed order — its lower band's, then its own band's, in index
// order — whatever the number of threads, and the results are the same bit for bit on any thread
// count. The vector sums have an order fixed by the target and the neighbour order.
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
#include <utility>
#include <variant>
#include <vector>

#include <hwy/highway.h>

#include "sluice/core/lanes-inl.hpp"
#include "sluice/physics/rate_loops.hpp"

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using simd::Pack;

#include "sluice/physics/kernel_shapes-inl.hpp"
#include "sluice/physics/pair_terms-inl.hpp"
#include "sluice/physics/wcsph_pair-inl.hpp"

// The neighbours of one particle: indices j and separations x_i - x_j, read contiguously by the pair
// loop. Room is kept for a whole vector past the end (compressed stores write whole vectors).
template <int Dim>
struct NeighborList {
  std::vector<std::int64_t> index;
  std::array<std::vector<double>, Dim> separation;
  std::size_t count = 0;

  void reserve(std::size_t n) {
    if (index.size() >= n) return;
    index.resize(2 * n);
    for (auto& s : separation) s.resize(2 * n);
  }
};

// f(begin, end) for each range of a CellGrid range list. (The loop is here, not a callback through
// CellGrid, which is compiled for the baseline instruction set and could not inline this target's f.)
template <class Ranges, class F>
HWY_INLINE void for_each_range(const Ranges& ranges, F&& f) {
  for (int k = 0; k < ranges.count; ++k) f(ranges.range[k].first, ranges.range[k].second);
}

// Collects the neighbours j of particle i (at xi) with min_r2 < r^2 < support2 among the candidate
// ranges; candidates of a range are consecutive indices, loaded a vector at a time.
template <int Dim, class Ranges>
HWY_INLINE void collect_neighbors(const Ranges& ranges, const std::array<double, Dim>& xi,
                                  const std::array<const double*, Dim>& x, double support2, double min_r2,
                                  NeighborList<Dim>& list) {
  const simd::D d;
  const simd::DI di;
  const std::size_t N = hn::Lanes(d);
  const auto upper = hn::Set(d, support2), lower = hn::Set(d, min_r2);
  std::size_t count = 0;
  for_each_range(ranges, [&](std::uint32_t begin, std::uint32_t end) {
    if (end <= begin) return;
    list.reserve(count + (end - begin) + N);
    for (std::uint32_t j = begin; j < end; j += static_cast<std::uint32_t>(N)) {
      const std::size_t lanes = std::min<std::size_t>(N, end - j);
      const auto valid = hn::FirstN(d, lanes);
      std::array<hn::Vec<simd::D>, Dim> dx;
      auto r2 = hn::Zero(d);
      for (int k = 0; k < Dim; ++k) {
        dx[k] = hn::Sub(hn::Set(d, xi[k]), simd::load_first(lanes, x[k] + j, 0.0).v);
        r2 = k == 0 ? hn::Mul(dx[k], dx[k]) : hn::Add(r2, hn::Mul(dx[k], dx[k]));
      }
      const auto hit = hn::And(valid, hn::And(hn::Lt(r2, upper), hn::Gt(r2, lower)));
      for (int k = 0; k < Dim; ++k) hn::StoreU(simd::compress(d, dx[k], hit), d, list.separation[k].data() + count);
      hn::StoreU(simd::compress(di, hn::Iota(di, j), hn::RebindMask(di, hit)), di, list.index.data() + count);
      count += hn::CountTrue(d, hit);
    }
  });
  list.count = count;
}

// Per-thread scratch of the pair loop: the neighbour list and the contributions to the neighbours.
template <int Dim>
struct PairScratch {
  NeighborList<Dim> neighbors;
  std::array<std::vector<double>, Dim> to_j;
  std::vector<double> to_j_rho;

  void reserve(std::size_t n) {
    neighbors.reserve(n);
    if (to_j_rho.size() >= n) return;
    for (auto& b : to_j) b.resize(2 * n);
    to_j_rho.resize(2 * n);
  }
};

// Pads the list to whole vectors with entries j = i placed outside the support, whose terms are
// exactly zero.
template <int Dim>
HWY_INLINE std::size_t pad_to_vectors(NeighborList<Dim>& list, std::uint32_t i, double outside) {
  const std::size_t N = simd::lanes();
  const std::size_t padded = (list.count + N - 1) / N * N;
  for (std::size_t k = list.count; k < padded; ++k) {
    list.index[k] = i;
    list.separation[0][k] = outside;
    for (int d = 1; d < Dim; ++d) list.separation[d][k] = 0.0;
  }
  return padded;
}

// The pairs of i with its listed neighbours: adds i's sums and the j's contributions to the rates.
// Returns the pair maxima (speed2, and the smallest fluid_r2) through `speed2_max` and `r2_min`.
template <int Dim, class Pair>
HWY_INLINE void evaluate_pairs(const Pair& pair, std::uint32_t i, PairScratch<Dim>& s, std::size_t padded,
                               const std::array<double*, Dim>& acc, double* density_rate, double& speed2_max,
                               double& r2_min) {
  const simd::DI di;
  const std::size_t N = simd::lanes();
  const auto si = pair.template side<Pack>([&](const double* a) { return Pack(a[i]); });
  std::array<Pack, Dim> sum;
  sum.fill(0.0);
  Pack drho = 0.0, vmax = 0.0, rmin = pair.far_r2;
  const NeighborList<Dim>& list = s.neighbors;
  for (std::size_t k = 0; k < padded; k += N) {
    const auto index = hn::LoadU(di, list.index.data() + k);
    std::array<Pack, Dim> r_ij;
    for (int d = 0; d < Dim; ++d) r_ij[d] = simd::load(list.separation[d].data() + k);
    const auto sj = pair.template side<Pack>([&](const double* a) { return simd::gather(a, index); });
    const auto out = pair(si, sj, r_ij);
    for (int d = 0; d < Dim; ++d) {
      sum[d] += out.force[d];
      simd::store(-out.force[d], s.to_j[d].data() + k);
    }
    drho += out.drho_i;
    simd::store(out.drho_j, s.to_j_rho.data() + k);
    vmax = simd::max(vmax, out.speed2);
    rmin = simd::min(rmin, out.fluid_r2);
  }
  // No two entries of the list are the same particle, and none is i.
  for (std::size_t k = 0; k < list.count; ++k) {
    const auto j = static_cast<std::size_t>(list.index[k]);
    for (int d = 0; d < Dim; ++d) acc[d][j] += s.to_j[d][k];
    density_rate[j] += s.to_j_rho[k];
  }
  for (int d = 0; d < Dim; ++d) acc[d][i] += simd::reduce_add(sum[d]);
  density_rate[i] += simd::reduce_add(drho);
  speed2_max = std::max(speed2_max, simd::reduce_max(vmax));
  r2_min = std::min(r2_min, simd::reduce_min(rmin));
}

// Gravity on the fluid, and the largest fluid acceleration and density.
template <int Dim>
HWY_INLINE void add_gravity(Particles<Dim>& p, const Vec<Dim>& g, const double* fluid, double& max_accel2,
                            double& max_rho) {
  const long n = static_cast<long>(p.size());
#pragma omp for schedule(static) reduction(max : max_accel2, max_rho)
  for (long i = 0; i < n; ++i) {
    max_rho = std::max(max_rho, p.density[i]);
    if (fluid[i] == 0.0) continue;
    double a2 = 0.0;
    for (int d = 0; d < Dim; ++d) {
      p.acceleration[d][i] += g[d];
      a2 += p.acceleration[d][i] * p.acceleration[d][i];
    }
    max_accel2 = std::max(max_accel2, a2);
  }
}

template <int Dim, class Kernel, class Walls, bool WithArtificialPressure>
RateSummary rate_loop(Particles<Dim>& p, const CellGrid<Dim>& grid, const RateSettings<Dim>& s,
                      const ParticleTerms& t, int threads) {
  const double support2 = Kernel::support * Kernel::support * s.h * s.h;
  const double min_r2 = 1e-18 * s.h * s.h;  // excludes i = j (and exactly coincident points)
  const auto pair = WcsphPair<Dim, Kernel, Walls, WithArtificialPressure>::of(p, s, t);
  const double outside = 1.5 * Kernel::support * s.h;

  const long n = static_cast<long>(p.size());
  std::array<const double*, Dim> x{};
  std::array<double*, Dim> acc{};
  for (int d = 0; d < Dim; ++d) {
    x[d] = p.position[d].data();
    acc[d] = p.acceleration[d].data();
  }
  double* const density_rate = p.density_rate.data();
  const double* const fluid = t.fluid_mask.data();
  const auto& cell_start = grid.cell_start();

  // Fluid particles before each sorted index: a wall particle with no fluid among its forward
  // candidates has only wall-wall pairs there (v_ij = 0, no diffusion, wall accelerations unused) and
  // is skipped.
  std::vector<std::uint32_t> fluid_before(static_cast<std::size_t>(n) + 1, 0);
  for (long i = 0; i < n; ++i) fluid_before[i + 1] = fluid_before[i] + (fluid[i] != 0.0);
  const long bands = static_cast<long>(grid.band_count());

  double max_accel2 = 0.0, max_speed2 = 0.0, max_rho = 0.0, closest2 = support2;
#pragma omp parallel num_threads(threads)
  {
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) {
      for (int d = 0; d < Dim; ++d) acc[d][i] = 0.0;
      density_rate[i] = 0.0;
    }
    PairScratch<Dim> scratch;
    scratch.reserve(512);
    for (long parity = 0; parity < 2; ++parity) {
#pragma omp for schedule(dynamic, 1) reduction(max : max_speed2) reduction(min : closest2)
      for (long band = parity; band < bands; band += 2) {
        const auto [first_cell, last_cell] = grid.band_cells(static_cast<std::size_t>(band));
        for (std::uint32_t cell = first_cell; cell < last_cell; ++cell) {
          const std::uint32_t cell_begin = cell_start[cell], cell_end = cell_start[cell + 1];
          if (cell_begin == cell_end) continue;
          const auto ranges = grid.forward_ranges(cell);
          for (std::uint32_t i = cell_begin; i < cell_end; ++i) {
            const auto forward = ranges.of(i);
            if (fluid[i] == 0.0) {
              bool near_fluid = false;
              for_each_range(forward, [&](std::uint32_t begin, std::uint32_t end) {
                near_fluid = near_fluid || (end > begin && fluid_before[end] > fluid_before[begin]);
              });
              if (!near_fluid) continue;
            }
            std::array<double, Dim> xi{};
            for (int d = 0; d < Dim; ++d) xi[d] = x[d][i];
            collect_neighbors<Dim>(forward, xi, x, support2, min_r2, scratch.neighbors);
            if (scratch.neighbors.count == 0) continue;
            scratch.reserve(scratch.neighbors.count + simd::lanes());
            const std::size_t padded = pad_to_vectors(scratch.neighbors, i, outside);
            evaluate_pairs<Dim>(pair, i, scratch, padded, acc, density_rate, max_speed2, closest2);
          }
        }
      }
    }
    add_gravity<Dim>(p, s.gravity, fluid, max_accel2, max_rho);
  }
  return {std::sqrt(max_accel2), std::sqrt(max_speed2), max_rho, std::sqrt(closest2)};
}

template <int Dim, class Kernel>
void shepard_loop(Particles<Dim>& p, const CellGrid<Dim>& grid, double h, double mass,
                  const std::vector<std::uint8_t>* selected, std::vector<double>& out, int threads) {
  const Kernel kernel(h);
  const long n = static_cast<long>(p.size());
  const std::size_t N = simd::lanes();
  const auto& cell_of = grid.cell_of();
  out.assign(p.density.begin(), p.density.end());
#pragma omp parallel for schedule(dynamic, 512) num_threads(threads)
  for (long i = 0; i < n; ++i) {
    if (!p.is_fluid(static_cast<std::size_t>(i)) || (selected && (*selected)[i] == 0)) continue;
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
          const Pack dx = xi[d] - simd::load_first(lanes, p.position[d].data() + j, d == 0 ? outside : 0.0);
          r2 += dx * dx;
        }
        const Pack w = shape::value_inside(kernel, simd::sqrt(r2));
        mass_sum += w;
        volume_sum += w * simd::quotient(mass, simd::load_first(lanes, p.density.data() + j, 1.0));
      }
    });
    out[i] = mass * simd::reduce_add(mass_sum) / simd::reduce_add(volume_sum);
  }
  p.density.swap(out);
}

// The table of this target's loops, one per kernel, wall treatment and artificial pressure switch.
template <int Dim, std::size_t K, std::size_t W>
void add_rate_loops(DimensionLoops<Dim>& loops) {
  using Kernel = std::variant_alternative_t<K, AnyKernel<Dim>>;
  using Walls = std::variant_alternative_t<W, WallTreatment>;
  loops.rates[K][W][0] = &rate_loop<Dim, Kernel, Walls, false>;
  loops.rates[K][W][1] = &rate_loop<Dim, Kernel, Walls, true>;
  if constexpr (W == 0) loops.shepard[K] = &shepard_loop<Dim, Kernel>;
}

template <int Dim, std::size_t K, std::size_t... W>
void add_kernel_loops(DimensionLoops<Dim>& loops, std::index_sequence<W...>) {
  (add_rate_loops<Dim, K, W>(loops), ...);
}

template <int Dim, std::size_t... K>
DimensionLoops<Dim> dimension_loops(std::index_sequence<K...>) {
  DimensionLoops<Dim> loops{};
  (add_kernel_loops<Dim, K>(loops, std::make_index_sequence<kWallTreatments>{}), ...);
  return loops;
}

inline const RateLoops* target_rate_loops() {
  static const RateLoops loops{hwy::TargetName(HWY_TARGET), dimension_loops<2>(std::make_index_sequence<kKernels>{}),
                                dimension_loops<3>(std::make_index_sequence<kKernels>{})};
  return &loops;
}

}  // namespace sluice::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
