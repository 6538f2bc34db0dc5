// Linked-cell neighbour search (cells of size = kernel support), rebuilt in O(N) by a counting sort.
//
// `bin` computes each particle's cell and a stable order that sorts particles by cell; the caller
// reorders the particle arrays with it, after which the particles of cell c are the contiguous
// index range [cell_start[c], cell_start[c+1]). Cells are numbered along the grid's axes, the first
// fastest, so the 3 cells of a row around a particle are one contiguous range: a 2D query visits 3
// ranges, a 3D query 9. The grid's last (slowest) axis is the space axis with the most cells, the
// others follow in x, y, z order; a tie keeps that order. Threads share the pair loop by bands of
// cells along that last axis (band_cells), so the longest axis gives the most bands: a dam break
// spreads along its tank, which holds many more columns of cells than it holds water rows. (The
// names below say x, y, z for the grid's axes 0, 1, 2.)
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "sluice/core/parallel.hpp"

namespace sluice {

template <int Dim>
class CellGrid {
 public:
  CellGrid() = default;

  // The grid covers [lower, upper]; particles outside are clamped into the edge cells, which keeps
  // the search correct (distances are always checked) if one strays.
  CellGrid(const std::array<double, Dim>& lower, const std::array<double, Dim>& upper, double cell_size)
      : cell_size_(cell_size), inv_cell_size_(1.0 / cell_size) {
    if (!(cell_size > 0.0)) throw std::invalid_argument("CellGrid: cell size must be positive");
    std::array<int, Dim> cells{};
    for (int d = 0; d < Dim; ++d) cells[d] = std::max(1, static_cast<int>(std::ceil((upper[d] - lower[d]) * inv_cell_size_)));
    // The slowest axis: the one with the most cells (the last of equals).
    int slowest = Dim - 1;
    for (int d = Dim - 2; d >= 0; --d)
      if (cells[d] > cells[slowest]) slowest = d;
    for (int d = 0, k = 0; d < Dim; ++d)
      if (d != slowest) axis_[k++] = d;
    axis_[Dim - 1] = slowest;
    std::size_t total = 1;
    for (int k = 0; k < Dim; ++k) {
      count_[k] = cells[axis_[k]];
      lower_[k] = lower[axis_[k]];
      total *= static_cast<std::size_t>(count_[k]);
    }
    if (total > (std::size_t{1} << 31)) throw std::invalid_argument("CellGrid: domain too large for the cell size");
    cell_start_.assign(total + 1, 0);
  }

  [[nodiscard]] double cell_size() const { return cell_size_; }
  [[nodiscard]] std::size_t cell_count() const { return cell_start_.size() - 1; }
  // Cells along space axis d (x, y or z).
  [[nodiscard]] int count(int d) const { return count_[grid_axis(d)]; }
  // The space axis of grid axis k (k = 0 is the fastest, Dim - 1 the band axis).
  [[nodiscard]] int axis(int k) const { return axis_[k]; }

  // Cell coordinate of a point's component x along space axis d, clamped to the grid.
  [[nodiscard]] int coordinate(double x, int d) const { return grid_coordinate(x, grid_axis(d)); }

  // Computes cell indices and the counting-sort order. After the caller permutes the particles
  // with `order()`, call nothing else: cell_start() and cell_of() already describe the sorted set.
  // With several threads (for many particles) the counting sort is parallel too: each thread counts
  // the cells of its contiguous share of the particles; the counts become each thread's starting
  // position in each cell by a scan over the cells that the threads share (each sums its share of the
  // cells, then scans it from the total of the shares before it: a tank is mostly air, and its cells
  // can be as many as its particles); and each thread places its share. Threads' shares are in index
  // order, so the order is the serial stable order whatever the number of threads.
  void bin(const std::array<std::vector<double>, Dim>& position, int threads = 1) {
    const long n = static_cast<long>(position[0].size());
    const std::size_t cells = cell_count();
    const int teams = n >= parallel::light_loop_threshold ? std::max(1, threads) : 1;
    cell_of_.resize(static_cast<std::size_t>(n));
    order_.resize(static_cast<std::size_t>(n));
    cursor_.resize(static_cast<std::size_t>(teams) * cells);
    odd_count_.resize(static_cast<std::size_t>(teams) * cells);
    cells_before_.assign(static_cast<std::size_t>(teams) + 1, 0u);
    parallel::in_team(teams, teams > 1, [&](const parallel::Team& team) {
      const long t = team.index(), size = team.size();
      const long begin = n * t / size, end = n * (t + 1) / size;
      std::uint32_t* __restrict count = cursor_.data() + static_cast<std::size_t>(t) * cells;
      std::fill(count, count + cells, 0u);
      // The cells first, in a loop of its own that the compiler can vectorise: its numbers in locals
      // (a store to cell_of_ could otherwise change the members, as far as the compiler knows).
      std::array<const double*, Dim> x{};
      std::array<double, Dim> lower{}, last{};
      std::array<std::uint32_t, Dim> along{};
      for (int k = 0; k < Dim; ++k) {
        x[k] = position[axis_[k]].data();
        lower[k] = lower_[k];
        last[k] = static_cast<double>(count_[k] - 1);
        along[k] = static_cast<std::uint32_t>(count_[k]);
      }
      const double inv = inv_cell_size_;
      std::uint32_t* __restrict cell = cell_of_.data();
      for (long i = begin; i < end; ++i) {
        std::uint32_t c = 0;
        for (int k = Dim - 1; k >= 0; --k) {
          const double u = (x[k][i] - lower[k]) * inv;
          // Clamped as grid_coordinate does (not a number: 0), without branches.
          const double clamped = u > 0.0 ? (u < last[k] ? u : last[k]) : 0.0;
          c = c * along[k] + static_cast<std::uint32_t>(static_cast<int>(clamped));
        }
        cell[i] = c;
      }
      // Counted in two tables, the even and the odd particles: the particles are in the last
      // binning's order, a cell's together, and with one table an increment would wait on the store
      // of the one before.
      std::uint32_t* __restrict odd = odd_count_.data() + static_cast<std::size_t>(t) * cells;
      std::fill(odd, odd + cells, 0u);
      long i = begin;
      for (; i + 1 < end; i += 2) {
        ++count[cell[i]];
        ++odd[cell[i + 1]];
      }
      if (i < end) ++count[cell[i]];
      for (std::size_t c = 0; c < cells; ++c) count[c] += odd[c];
      team.barrier();
      const std::size_t c_begin = cells * static_cast<std::size_t>(t) / static_cast<std::size_t>(size);
      const std::size_t c_end = cells * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(size);
      std::uint32_t share = 0;
      for (long u = 0; u < size; ++u) {
        const std::uint32_t* counts = cursor_.data() + static_cast<std::size_t>(u) * cells;
        for (std::size_t c = c_begin; c < c_end; ++c) share += counts[c];
      }
      cells_before_[static_cast<std::size_t>(t) + 1] = share;
      team.barrier();
      std::uint32_t running = 0;
      for (long u = 0; u <= t; ++u) running += cells_before_[static_cast<std::size_t>(u)];
      for (std::size_t c = c_begin; c < c_end; ++c) {
        cell_start_[c] = running;
        for (long u = 0; u < size; ++u) {
          std::uint32_t& slot = cursor_[static_cast<std::size_t>(u) * cells + c];
          const std::uint32_t k = slot;
          slot = running;
          running += k;
        }
      }
      if (t == size - 1) cell_start_[cells] = running;
      team.barrier();
      for (long i = begin; i < end; ++i) order_[count[cell[i]]++] = static_cast<std::uint32_t>(i);
      team.barrier();
      // Cell of each particle in sorted order, written over the unsorted cells, which no thread reads
      // any more: the particles of this thread's share of the cells (the region's end is the barrier).
      for (std::size_t c = c_begin; c < c_end; ++c)
        std::fill(cell_of_.begin() + cell_start_[c], cell_of_.begin() + cell_start_[c + 1], static_cast<std::uint32_t>(c));
    });
  }

  // After the caller removed the particles with keep[i] == 0 (keeping the others' order): the cells
  // of the ones kept, as they were binned (cell_start() and cell_of() describe the smaller set).
  void keep(const std::vector<std::uint8_t>& keep) {
    const std::size_t n = cell_of_.size(), cells = cell_count();
    std::size_t k = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i]) cell_of_[k++] = cell_of_[i];
    cell_of_.resize(k);
    std::fill(cell_start_.begin(), cell_start_.end(), 0u);
    for (std::size_t i = 0; i < k; ++i) ++cell_start_[cell_of_[i] + 1];
    for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  }

  [[nodiscard]] const std::vector<std::uint32_t>& order() const { return order_; }
  [[nodiscard]] const std::vector<std::uint32_t>& cell_of() const { return cell_of_; }
  [[nodiscard]] const std::vector<std::uint32_t>& cell_start() const { return cell_start_; }

  // Contiguous ranges [first, second) of (sorted) particle indices, as data: code compiled for
  // another instruction set (the pair loop) loops over them itself instead of passing a callback.
  template <std::size_t N>
  struct RangeList {
    std::array<std::pair<std::uint32_t, std::uint32_t>, N> range{};
    int count = 0;
    void add(std::uint32_t begin, std::uint32_t end) { range[count++] = {begin, end}; }
  };
  using NeighborRanges = RangeList<Dim == 1 ? 1 : (Dim == 2 ? 3 : 9)>;

  // The ranges that cover the cells adjacent to cell `c` (including c): one per row of cells.
  [[nodiscard]] NeighborRanges neighbor_ranges(std::uint32_t c) const {
    NeighborRanges r = neighbor_cells(c);
    for (int k = 0; k < r.count; ++k) r.range[k] = {cell_start_[r.range[k].first], cell_start_[r.range[k].second]};
    return r;
  }

  // Cell c's coordinates along the grid's axes, and the first and last of the columns (along the
  // grid's first axis) adjacent to it.
  struct CellPlace {
    std::array<int, Dim> coord{};
    int x_lo = 0, x_hi = 0;
  };
  [[nodiscard]] CellPlace place_of(std::uint32_t c) const {
    CellPlace place;
    std::uint32_t rest = c;
    for (int d = 0; d < Dim; ++d) {
      place.coord[d] = static_cast<int>(rest % static_cast<std::uint32_t>(count_[d]));
      rest /= static_cast<std::uint32_t>(count_[d]);
    }
    place.x_lo = std::max(place.coord[0] - 1, 0);
    place.x_hi = std::min(place.coord[0] + 1, count_[0] - 1);
    return place;
  }

  // The same rows as ranges of cell indices [first, second): the cells adjacent to cell `c`.
  [[nodiscard]] NeighborRanges neighbor_cells(std::uint32_t c) const {
    // Named copies, not a structured binding: the lambdas below capture them (clang 14 cannot capture a binding).
    const CellPlace place = place_of(c);
    const auto& coord = place.coord;
    const int x_lo = place.x_lo, x_hi = place.x_hi;
    NeighborRanges r;
    const auto add = [&](std::size_t row) {
      r.add(static_cast<std::uint32_t>(row + x_lo), static_cast<std::uint32_t>(row + x_hi + 1));
    };
    if constexpr (Dim == 1) {
      add(0);
    } else if constexpr (Dim == 2) {
      for (int y = std::max(coord[1] - 1, 0); y <= std::min(coord[1] + 1, count_[1] - 1); ++y)
        add(static_cast<std::size_t>(y) * count_[0]);
    } else {
      for (int z = std::max(coord[2] - 1, 0); z <= std::min(coord[2] + 1, count_[2] - 1); ++z)
        for (int y = std::max(coord[1] - 1, 0); y <= std::min(coord[1] + 1, count_[1] - 1); ++y)
          add((static_cast<std::size_t>(z) * count_[1] + y) * count_[0]);
    }
    return r;
  }

  // Calls f(begin, end) for each range of neighbor_ranges(c).
  template <class F>
  void for_each_neighbor_range(std::uint32_t c, F&& f) const {
    const NeighborRanges r = neighbor_ranges(c);
    for (int k = 0; k < r.count; ++k) f(r.range[k].first, r.range[k].second);
  }

  // The cell that holds point x (clamped into the grid, as particles are binned): with
  // neighbor_ranges, the candidates within one cell size of any point.
  [[nodiscard]] std::uint32_t cell_at(const std::array<double, Dim>& x) const {
    std::uint32_t c = 0;
    for (int k = Dim - 1; k >= 0; --k)
      c = c * static_cast<std::uint32_t>(count_[k]) + static_cast<std::uint32_t>(grid_coordinate(x[axis_[k]], k));
    return c;
  }

  // Calls f(begin, end) for each contiguous range of (sorted) particle indices covering the cells
  // that overlap the box [lower, upper]: one range per row of cells, in increasing index order.
  template <class F>
  void for_each_range_in_box(const std::array<double, Dim>& lower, const std::array<double, Dim>& upper,
                             F&& f) const {
    std::array<int, Dim> lo{}, hi{};  // along the grid's axes
    for (int k = 0; k < Dim; ++k) {
      lo[k] = grid_coordinate(lower[axis_[k]], k);
      hi[k] = grid_coordinate(upper[axis_[k]], k);
    }
    std::array<int, Dim> at = lo;
    while (true) {
      std::size_t row = 0;  // index of the row's first cell: x fastest, then y, then z
      for (int d = Dim - 1; d >= 1; --d) row = row * static_cast<std::size_t>(count_[d]) + static_cast<std::size_t>(at[d]);
      row *= static_cast<std::size_t>(count_[0]);
      f(cell_start_[row + lo[0]], cell_start_[row + hi[0] + 1]);
      int d = 1;
      while (d < Dim && ++at[d] > hi[d]) at[d] = lo[d], ++d;
      if (d >= Dim) return;
    }
  }

  // The "forward" half of the neighbours of a particle i in cell c: the particles after i in its own
  // cell and those of the adjacent cells that come later in the cell order. Over all i, every pair of
  // particles in adjacent cells is visited exactly once, from its first particle. Cells are numbered
  // with x fastest, so the forward cells of i's row are one range with i's own cell, [i + 1, own_end);
  // the other ranges (the row above in 2D; also the plane above in 3D) are the same for every
  // particle of the cell, so a loop over the particles of a cell computes them once.
  struct ForwardRanges {
    std::uint32_t own_end = 0;
    std::array<std::pair<std::uint32_t, std::uint32_t>, Dim == 3 ? 4 : Dim - 1> other{};
    int others = 0;

    // The forward ranges of particle i of the cell, as data.
    [[nodiscard]] RangeList<(Dim == 3 ? 4 : Dim - 1) + 1> of(std::uint32_t i) const {
      RangeList<(Dim == 3 ? 4 : Dim - 1) + 1> list;
      list.add(i + 1, own_end);
      for (int k = 0; k < others; ++k) list.add(other[k].first, other[k].second);
      return list;
    }
  };

  [[nodiscard]] ForwardRanges forward_ranges(std::uint32_t c) const {
    // Named copies, not a structured binding: the lambdas below capture them (clang 14 cannot capture a binding).
    const CellPlace place = place_of(c);
    const auto& coord = place.coord;
    const int x_lo = place.x_lo, x_hi = place.x_hi;
    const std::size_t own_row = c - static_cast<std::uint32_t>(coord[0]);
    ForwardRanges r;
    r.own_end = cell_start_[own_row + x_hi + 1];
    const auto add = [&](std::size_t row) { r.other[r.others++] = {cell_start_[row + x_lo], cell_start_[row + x_hi + 1]}; };
    if constexpr (Dim >= 2) {
      if (coord[1] + 1 < count_[1]) add(own_row + count_[0]);
    }
    if constexpr (Dim == 3) {
      if (coord[2] + 1 < count_[2])
        for (int y = std::max(coord[1] - 1, 0); y <= std::min(coord[1] + 1, count_[1] - 1); ++y)
          add((static_cast<std::size_t>(coord[2] + 1) * count_[1] + y) * count_[0]);
    }
    return r;
  }

  // Calls f(begin, end) for the forward ranges of particle i in cell c (see ForwardRanges).
  template <class F>
  static void for_each_forward_range(std::uint32_t i, const ForwardRanges& r, F&& f) {
    const auto list = r.of(i);
    for (int k = 0; k < list.count; ++k) f(list.range[k].first, list.range[k].second);
  }
  template <class F>
  void for_each_forward_range(std::uint32_t i, std::uint32_t c, F&& f) const {
    for_each_forward_range(i, forward_ranges(c), f);
  }

  // The cells of band b: [first, last) cell indices.
  [[nodiscard]] std::pair<std::uint32_t, std::uint32_t> band_cells(std::size_t b) const {
    const std::size_t stride = cell_count() / band_count();
    return {static_cast<std::uint32_t>(b * stride), static_cast<std::uint32_t>((b + 1) * stride)};
  }

  // Thread t's share of the bands for the pair loop: [begin, end), a contiguous run, with the runs of
  // the `threads` threads in order and of about equal cost, from `fluid_before` (the fluid particles
  // before each sorted index, n + 1 of them): a fluid particle counts as eight wall particles, as a
  // wall particle only meets the fluid. Which thread takes a band does not change the pair loop's
  // results: bands of one parity are done before those of the other, and within a band in order. A
  // contiguous run, rather than bands handed out in turn, keeps a band's particles with one core from
  // the even pass to the odd one and from one evaluation to the next.
  [[nodiscard]] std::pair<long, long> thread_bands(const std::vector<std::uint32_t>& fluid_before, int t,
                                                   int threads) const {
    const long bands = static_cast<long>(band_count());
    const auto cost_before = [&](long band) {
      const std::uint32_t i = cell_start_[band_cells(static_cast<std::size_t>(band)).first];
      return static_cast<double>(i) + 7.0 * static_cast<double>(fluid_before[i]);
    };
    const auto split = [&](int k) -> long {
      if (k <= 0) return 0;
      if (k >= threads) return bands;
      const double target = cost_before(bands) * k / threads;
      long lo = 0, hi = bands;  // the first band whose cost before it reaches the target
      while (lo < hi) {
        const long mid = lo + (hi - lo) / 2;
        if (cost_before(mid) < target)
          lo = mid + 1;
        else
          hi = mid;
      }
      return lo;
    };
    return {split(t), split(t + 1)};
  }

  // Bands: the layers of cells along the slowest coordinate (rows in 2D, planes in 3D). The forward
  // neighbours of a particle lie in its own band and the next one, so bands of the same parity can be
  // processed at the same time without two of them writing to the same particle.
  [[nodiscard]] std::size_t band_count() const { return static_cast<std::size_t>(count_[Dim - 1]); }
 private:
  [[nodiscard]] int grid_axis(int d) const {
    int k = 0;
    while (axis_[k] != d) ++k;
    return k;
  }
  // floor((x - lower) / cell size), clamped to [0, count - 1]: clamped first, the conversion's
  // truncation is the floor (the values are then at least 0), with no floor call (the baseline x86-64
  // has no rounding instruction, and GCC emulates it in ten). A coordinate that is not a number goes
  // to cell 0 (std::max(0.0, NaN) is 0.0; std::clamp would pass the NaN on, and converting it to int
  // is undefined): the instability guard reports the particle after the step.
  [[nodiscard]] int grid_coordinate(double x, int k) const {
    const double c = (x - lower_[k]) * inv_cell_size_;
    return static_cast<int>(std::min(static_cast<double>(count_[k] - 1), std::max(0.0, c)));
  }

  // Along the grid's axes (k = 0 fastest): the space axis, the lower corner and the number of cells.
  std::array<int, Dim> axis_ = [] {
    std::array<int, Dim> a{};
    for (int d = 0; d < Dim; ++d) a[d] = d;
    return a;
  }();
  std::array<double, Dim> lower_{};
  std::array<int, Dim> count_{};
  double cell_size_ = 1.0;
  double inv_cell_size_ = 1.0;
  std::vector<std::uint32_t> cell_start_{0};
  std::vector<std::uint32_t> cell_of_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> cursor_;
  std::vector<std::uint32_t> odd_count_;  // bin(): the odd particles' counts, per thread
  std::vector<std::uint32_t> cells_before_;  // bin: the particles in the cells of the threads before each
};

}  // namespace sluice
