// The linked-cell search finds exactly the pairs a brute-force search finds, and sorts by cell; the
// particles follow the order.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <limits>
#include <atomic>
#include <random>
#include <set>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"

using namespace sluice;

// A wide box (4 x 2) and a tall one (2 x 4): long and short rows of cells.
class CellGridBox : public ::testing::TestWithParam<bool> {};

TEST_P(CellGridBox, FindsTheSamePairsAsBruteForce) {
  const bool tall = GetParam();
  const std::array<double, 2> lo = tall ? std::array<double, 2>{0.0, -1.0} : std::array<double, 2>{-1.0, 0.0};
  const std::array<double, 2> hi = tall ? std::array<double, 2>{2.0, 3.0} : std::array<double, 2>{3.0, 2.0};
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> ux(lo[0], hi[0]), uy(lo[1], hi[1]);
  const std::size_t n = 3000;
  std::array<std::vector<double>, 2> pos;
  for (std::size_t i = 0; i < n; ++i) {
    pos[0].push_back(ux(rng));
    pos[1].push_back(uy(rng));
  }
  // Two strays outside the grid bounds must still be found by distance.
  pos[0].push_back(-5.0);
  pos[1].push_back(1.0);
  pos[0].push_back(-5.05);
  pos[1].push_back(1.0);
  const double radius = 0.13;
  CellGrid<2> grid(lo, hi, radius);
  EXPECT_EQ(grid.count(0), tall ? 16 : 31);
  EXPECT_EQ(grid.count(1), tall ? 31 : 16);
  grid.bin(pos);
  const auto& order = grid.order();
  ASSERT_EQ(order.size(), n + 2);
  // Sorted order visits cells in non-decreasing order.
  for (std::size_t k = 1; k < order.size(); ++k) ASSERT_LE(grid.cell_of()[k - 1], grid.cell_of()[k]);

  std::set<std::pair<std::uint32_t, std::uint32_t>> found, expected;
  for (std::size_t k = 0; k < order.size(); ++k) {
    grid.for_each_neighbor_range(grid.cell_of()[k], [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t kj = b; kj < e; ++kj) {
        const auto i = order[k], j = order[kj];
        if (i == j) continue;
        const double dx = pos[0][i] - pos[0][j], dy = pos[1][i] - pos[1][j];
        if (dx * dx + dy * dy < radius * radius) found.insert({i, j});
      }
    });
  }
  for (std::uint32_t i = 0; i < pos[0].size(); ++i)
    for (std::uint32_t j = 0; j < pos[0].size(); ++j) {
      if (i == j) continue;
      const double dx = pos[0][i] - pos[0][j], dy = pos[1][i] - pos[1][j];
      if (dx * dx + dy * dy < radius * radius) expected.insert({i, j});
    }
  EXPECT_GT(expected.size(), 1000u);
  EXPECT_EQ(found, expected);

  // The forward ranges visit every pair in adjacent cells once, from the particle that comes first.
  std::set<std::pair<std::uint32_t, std::uint32_t>> forward;
  for (std::uint32_t k = 0; k < order.size(); ++k) {
    grid.for_each_forward_range(k, grid.cell_of()[k], [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t kj = b; kj < e; ++kj) {
        const auto i = order[k], j = order[kj];
        const double dx = pos[0][i] - pos[0][j], dy = pos[1][i] - pos[1][j];
        if (dx * dx + dy * dy < radius * radius) {
          EXPECT_TRUE(forward.insert({std::min(i, j), std::max(i, j)}).second) << i << " " << j;
        }
      }
    });
  }
  EXPECT_EQ(forward.size(), expected.size() / 2);
}

INSTANTIATE_TEST_SUITE_P(WideAndTall, CellGridBox, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "Tall" : "Wide"; });

// A position that is not a number (a run gone unstable, before the guard sees it) must bin into a cell
// of the grid: converting the NaN to a cell index is undefined, and wrote the counts out of bounds.
TEST(CellGrid, PositionsThatAreNotNumbersBinIntoTheGrid) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  CellGrid<2> grid({0.0, 0.0}, {4.0, 2.0}, 0.5);
  std::array<std::vector<double>, 2> x = {std::vector<double>{nan, 1.0, inf, -inf, 3.9, nan},
                                          std::vector<double>{0.2, nan, 1.0, -inf, inf, -nan}};
  for (int threads : {1, 2}) {
    grid.bin(x, threads);
    std::vector<std::uint32_t> order = grid.order();
    std::sort(order.begin(), order.end());
    for (std::uint32_t i = 0; i < order.size(); ++i) EXPECT_EQ(order[i], i);
    for (std::uint32_t c : grid.cell_of()) EXPECT_LT(c, grid.cell_count());
    EXPECT_EQ(grid.cell_start().back(), 6u);
  }
  EXPECT_EQ(grid.coordinate(nan, 0), 0);
  EXPECT_EQ(grid.coordinate(inf, 0), grid.count(0) - 1);
  EXPECT_EQ(grid.coordinate(-inf, 1), 0);
}

TEST(CellGrid, RejectsNonPositiveCellSize) {
  EXPECT_THROW(CellGrid<2>({0, 0}, {1, 1}, 0.0), std::invalid_argument);
}

// Above parallel::light_loop_threshold particles the counting sort runs on the threads; the order must
// be the serial stable order (by cell, then by index) whatever the number of threads.
TEST(CellGrid, ParallelSortIsTheSerialStableOrder) {
  const std::size_t n = 3 * static_cast<std::size_t>(parallel::light_loop_threshold) + 17;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 4.0);
  std::array<std::vector<double>, 2> pos;
  for (std::size_t i = 0; i < n; ++i) {
    // Coarse positions, so that many particles share a cell and stability matters.
    pos[0].push_back(std::floor(u(rng) * 8.0) / 8.0 + 0.01);
    pos[1].push_back(u(rng));
  }
  // Cells fewer than the particles, and (a mostly empty tank) more: the threads share the scan over
  // the cells.
  for (double cell_size : {0.25, 0.01}) {
    std::vector<std::uint32_t> expected(n);
    CellGrid<2> serial({0.0, 0.0}, {4.0, 4.0}, cell_size);
    serial.bin(pos, 1);
    for (std::size_t i = 0; i < n; ++i) expected[i] = static_cast<std::uint32_t>(i);
    std::vector<std::uint32_t> cell(n);
    for (std::size_t i = 0; i < n; ++i)
      cell[i] = static_cast<std::uint32_t>(serial.coordinate(pos[1][i], 1) * serial.count(0) + serial.coordinate(pos[0][i], 0));
    std::stable_sort(expected.begin(), expected.end(), [&](std::uint32_t a, std::uint32_t b) { return cell[a] < cell[b]; });
    EXPECT_EQ(serial.order(), expected);
    for (int threads : {2, 3}) {
      CellGrid<2> grid({0.0, 0.0}, {4.0, 4.0}, cell_size);
      grid.bin(pos, threads);
      EXPECT_EQ(grid.order(), expected) << threads << " threads, cells " << cell_size;
      EXPECT_EQ(grid.cell_start(), serial.cell_start()) << threads << " threads, cells " << cell_size;
      EXPECT_EQ(grid.cell_of(), serial.cell_of()) << threads << " threads, cells " << cell_size;
    }
  }
}

// The pair loop's shares of the bands: contiguous, in order, covering every band, and of about equal
// cost (a fluid particle eight times a wall particle) to within one band's.
TEST(CellGrid, ThreadBandsAreContiguousRunsOfEqualCost) {
  const std::size_t n = 40000;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::array<std::vector<double>, 2> pos;
  std::vector<double> fluid;
  for (std::size_t i = 0; i < n; ++i) {
    // Water in the lower left, walls spread over the whole box.
    const bool water = i % 3 != 0;
    pos[0].push_back(water ? 3.0 * u(rng) * u(rng) : 4.0 * u(rng));
    pos[1].push_back(water ? 0.5 * u(rng) : 2.0 * u(rng));
    fluid.push_back(water ? 1.0 : 0.0);
  }
  CellGrid<2> grid({0.0, 0.0}, {4.0, 2.0}, 0.05);
  grid.bin(pos, 1);
  std::vector<std::uint32_t> before(n + 1, 0);
  for (std::size_t k = 0; k < n; ++k) before[k + 1] = before[k] + (fluid[grid.order()[k]] != 0.0);
  const long bands = static_cast<long>(grid.band_count());
  const auto cost = [&](long b) {
    const std::uint32_t i = grid.cell_start()[grid.band_cells(static_cast<std::size_t>(b)).first];
    return static_cast<double>(i) + 7.0 * static_cast<double>(before[i]);
  };
  double widest = 0.0;
  for (long b = 0; b < bands; ++b) widest = std::max(widest, cost(b + 1) - cost(b));
  for (int threads : {1, 2, 3, 5}) {
    long next = 0;
    for (int t = 0; t < threads; ++t) {
      const auto [begin, end] = grid.thread_bands(before, t, threads);
      EXPECT_EQ(begin, next) << threads << " threads, thread " << t;
      EXPECT_LE(begin, end);
      EXPECT_NEAR(cost(end) - cost(begin), cost(bands) / threads, widest) << threads << " threads, thread " << t;
      next = end;
    }
    EXPECT_EQ(next, bands) << threads << " threads";
  }
}

// parallel::prefix_count: the counts before each index, the same on any number of threads.
TEST(Parallel, PrefixCountIsTheSerialCount) {
  const long n = 3 * parallel::light_loop_threshold + 5;
  std::vector<std::uint8_t> flag(static_cast<std::size_t>(n));
  std::mt19937 rng(3);
  for (auto& f : flag) f = rng() % 3 == 0;
  std::vector<std::uint32_t> expected(static_cast<std::size_t>(n) + 1, 0);
  for (long i = 0; i < n; ++i) expected[i + 1] = expected[i] + flag[i];
  for (int threads : {1, 2, 3}) {
    std::vector<std::uint32_t> before;
    parallel::prefix_count(n, threads, before, [&](long i) { return flag[i] != 0; });
    EXPECT_EQ(before, expected) << threads << " threads";
  }
}

// Particles::permute moves every field with the particle, on one or several threads (above the
// threshold the copies run in one parallel region), with or without the step-start state.
TEST(Particles, PermuteMovesEveryFieldWithTheParticle) {
  // n = 40001 = 13 * 17 * 181: the residues mod 3 and 5 used below are not preserved by the order.
  const std::size_t n = 2 * static_cast<std::size_t>(parallel::light_loop_threshold) + 1;
  const auto make = [n] {
    Particles<2> p;
    for (std::size_t i = 0; i < n; ++i) p.add({0.5 * i, 1.5 * i}, i % 3 ? Kind::fluid : Kind::wall, 1000.0 + i);
    p.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      p.velocity[0][i] = 2.0 * i;
      p.velocity[1][i] = -2.0 * i;
      p.position_start[0][i] = 3.0 * i;
      p.position_start[1][i] = 4.0 * i;
      p.velocity_start[0][i] = 5.0 * i;
      p.velocity_start[1][i] = 6.0 * i;
      p.density_start[i] = 7.0 * i;
      p.needs_density_repair[i] = i % 5 == 0;
    }
    return p;
  };
  std::vector<std::uint32_t> order(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = static_cast<std::uint32_t>((k * 7919) % n);  // 7919 is prime, n is not a multiple
  for (int threads : {1, 2}) {
    Particles<2> p = make();
    std::vector<double> scratch;
    p.permute(order, scratch, true, threads);
    for (std::size_t k = 0; k < n; ++k) {
      const double i = order[k];
      ASSERT_EQ(p.id[k], order[k]) << threads;
      ASSERT_EQ(p.position[0][k], 0.5 * i);
      ASSERT_EQ(p.position[1][k], 1.5 * i);
      ASSERT_EQ(p.velocity[0][k], 2.0 * i);
      ASSERT_EQ(p.velocity[1][k], -2.0 * i);
      ASSERT_EQ(p.density[k], 1000.0 + i);
      ASSERT_EQ(p.kind[k], order[k] % 3 ? Kind::fluid : Kind::wall);
      ASSERT_EQ(p.position_start[0][k], 3.0 * i);
      ASSERT_EQ(p.position_start[1][k], 4.0 * i);
      ASSERT_EQ(p.velocity_start[0][k], 5.0 * i);
      ASSERT_EQ(p.velocity_start[1][k], 6.0 * i);
      ASSERT_EQ(p.density_start[k], 7.0 * i);
      ASSERT_EQ(p.needs_density_repair[k], order[k] % 5 == 0);
    }
    // The rates, recomputed after a reordering, were the spare arrays: the scratch took no memory.
    EXPECT_EQ(scratch.capacity(), 0u) << threads;
    // Without the step-start state, it stays where it was.
    Particles<2> q = make();
    q.permute(order, scratch, false, threads);
    ASSERT_EQ(q.density_start[1], 7.0);
    ASSERT_EQ(q.density[1], 1000.0 + order[1]);
    // Particles with their state only (no rates) reorder through the scratch.
    Particles<2> r;
    for (std::size_t i = 0; i < n; ++i) r.add({0.5 * i, 1.5 * i}, Kind::fluid, 1000.0 + i);
    r.permute(order, scratch, false, threads);
    EXPECT_EQ(scratch.size(), n);
    for (std::size_t k = 0; k < n; ++k) {
      ASSERT_EQ(r.position[1][k], 1.5 * order[k]);
      ASSERT_EQ(r.density[k], 1000.0 + order[k]);
    }
    scratch = {};
  }
}

// parallel::for_each_dynamic (contiguous shares with stealing) visits every index exactly once on any
// number of threads, also when the work is all in one thread's share.
// A team of one thread runs outside any parallel region, with no barrier (libgomp's barrier and the end
// of a region of one thread each make a futex system call: 16 a step of the default case); inside
// another region it is still a team of its own, so the passes that share out work by the team's
// index stay right there.
TEST(Parallel, ATeamOfOneRunsWithoutARegionAndStaysItsOwnTeamInsideOne) {
  bool in_region = true;
  parallel::in_team(1, true, [&](const parallel::Team& team) {
    in_region = omp_get_level() > 0;  // counts regions of one thread too, unlike omp_in_parallel
    team.barrier();
    EXPECT_EQ(team.index(), 0);
    EXPECT_EQ(team.size(), 1);
  });
  EXPECT_FALSE(in_region);
  const long n = 3 * parallel::light_loop_threshold + 7;
  std::vector<std::uint32_t> expected(static_cast<std::size_t>(n) + 1, 0);
  for (long i = 0; i < n; ++i) expected[static_cast<std::size_t>(i) + 1] = expected[static_cast<std::size_t>(i)] + (i % 3 == 0);
  std::vector<std::vector<std::uint32_t>> got(2);
  std::vector<int> sizes(2, 0);
#pragma omp parallel num_threads(2)
  {
    const int t = omp_get_thread_num();
    parallel::prefix_count(n, 1, got[static_cast<std::size_t>(t)], [](long i) { return i % 3 == 0; });
    parallel::in_team(1, false, [&](const parallel::Team& team) { sizes[static_cast<std::size_t>(t)] = team.size(); });
  }
  for (int t = 0; t < omp_get_max_threads() && t < 2; ++t) {
    if (got[static_cast<std::size_t>(t)].empty()) continue;  // the region ran on fewer threads
    EXPECT_EQ(got[static_cast<std::size_t>(t)], expected) << t;
    EXPECT_EQ(sizes[static_cast<std::size_t>(t)], 1) << t;
  }
}

TEST(Parallel, StealingVisitsEveryIndexOnce) {
  const long n = 10007;
  for (int threads : {1, 2, 3, 4}) {
    std::vector<std::atomic<int>> visits(static_cast<std::size_t>(n));
    parallel::for_each_dynamic(n, threads, 64, [&](long i) {
      if (i < n / 4) {  // the first share costs far more than the rest
        volatile double x = 0.0;
        for (int k = 0; k < 2000; ++k) x = x + 1.0;
      }
      ++visits[static_cast<std::size_t>(i)];
    });
    long wrong = 0;
    for (const auto& v : visits) wrong += v.load() != 1;
    EXPECT_EQ(wrong, 0) << threads << " threads";
  }
  // The runs themselves: items first, first + stride, ..., last, each handed out once.
  parallel::StealingRuns runs(2);
  runs.set(0, 0, 8);   // 0 2 4 6 8
  runs.set(1, 1, -1);  // empty
  std::vector<long> got;
  for (long k = runs.next(1, 2); k >= 0; k = runs.next(1, 2)) got.push_back(k);  // steals from the back
  EXPECT_EQ(got, (std::vector<long>{8, 6, 4, 2, 0}));
  EXPECT_EQ(runs.next(0, 2), -1);
}
