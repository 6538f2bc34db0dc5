// The MPI runtime (mpi/mpi_communicator.hpp) on the processes mpiexec started: the reductions, the
// messages, Zoltan's boxes and the session. tests/CMakeLists.txt runs it under mpiexec on 1 to 4
// processes (and the boxes on 6), and without mpiexec, where only the session's test runs: MPI must
// then be left alone.
// Every test makes the same collective calls in the same order on every process and only then
// checks, so that a failure on one process cannot leave the others waiting. Rank 0 prints gtest's
// report, the other ranks their failures only; the exit status is agreed by all ranks.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "sluice/mpi/mpi_communicator.hpp"

namespace {

using sluice::Communicator;
using sluice::DomainBox;
using Points = std::vector<std::array<double, 3>>;

constexpr double inf = std::numeric_limits<double>::infinity();

const sluice::MpiSession* session = nullptr;
const Communicator* comm = nullptr;  // the session's, or one of one process under mpiexec -np 1

#define NEEDS_PROCESSES()                                   \
  if (comm == nullptr) GTEST_SKIP() << "runs under mpiexec"; \
  const int n = comm->size();                                \
  const int me = comm->rank();                               \
  (void)n;                                                   \
  (void)me

// ---- Session ----

TEST(Session, WithoutLauncherLeavesMpiAlone) {
  if (session != nullptr) GTEST_SKIP() << "runs without mpiexec";
  EXPECT_FALSE(sluice::launched_by_mpi());
  int argc = 1;
  char name[] = "test";
  char* args[] = {name, nullptr};
  char** argv = args;
  EXPECT_EQ(sluice::start_mpi_if_launched(argc, argv), nullptr);
  int started = 1, stopped = 1;
  MPI_Initialized(&started);
  MPI_Finalized(&stopped);
  EXPECT_EQ(started, 0) << "MPI was started without a launcher";
  EXPECT_EQ(stopped, 0);
  // Each launcher's variable alone is enough.
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    ASSERT_EQ(::setenv(variable, "2", 1), 0);
    EXPECT_TRUE(sluice::launched_by_mpi()) << variable;
    ASSERT_EQ(::unsetenv(variable), 0);
  }
  EXPECT_FALSE(sluice::launched_by_mpi());
}

TEST(Session, UnderLauncher) {
  if (session == nullptr) GTEST_SKIP() << "runs under mpiexec";
  EXPECT_TRUE(sluice::launched_by_mpi());
  int started = 0, level = MPI_THREAD_SINGLE, size = 0, rank = -1;
  MPI_Initialized(&started);
  MPI_Query_thread(&level);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  EXPECT_EQ(started, 1);
  EXPECT_GE(level, MPI_THREAD_FUNNELED);
  EXPECT_EQ(session->size(), size);
  EXPECT_EQ(session->rank(), rank);
  EXPECT_GE(session->init_seconds(), 0.0);
  // One process is the serial code: no communicator.
  if (size == 1) {
    EXPECT_EQ(session->world(), nullptr);
  } else {
    ASSERT_NE(session->world(), nullptr);
    EXPECT_EQ(session->world()->size(), size);
    EXPECT_EQ(session->world()->rank(), rank);
    EXPECT_EQ(session->world()->is_root(), rank == 0);
  }
}

// ---- Reductions ----

TEST(Reducer, SumOfDoublesIsAddedInRankOrder) {
  NEEDS_PROCESSES();
  // 1e16 + 1 rounds back to 1e16 (its spacing is 2): the order of the additions shows in the result.
  auto part = [](int r) { return r == 0 ? 1e16 : r % 2 == 1 ? 1.0 : 0.75 + r; };
  double expected = part(0);
  for (int r = 1; r < n; ++r) expected += part(r);
  const double got = comm->reducer().sum(part(me));
  EXPECT_EQ(got, expected);
  const double simple = comm->reducer().sum(me + 0.25);
  EXPECT_EQ(simple, n * (n - 1) / 2.0 + 0.25 * n);
}

TEST(Reducer, SumOfIntegers) {
  NEEDS_PROCESSES();
  const std::int64_t part = std::int64_t{3'000'000'000} * (me + 1) - 7;
  const std::int64_t got = comm->reducer().sum(part);
  EXPECT_EQ(got, std::int64_t{3'000'000'000} * n * (n + 1) / 2 - 7 * n);
}

TEST(Reducer, MaxAndMin) {
  NEEDS_PROCESSES();
  auto part = [](int r) { return std::sin(r + 1.0) * (r + 1); };
  double highest = -inf, lowest = inf;
  for (int r = 0; r < n; ++r) {
    highest = std::max(highest, part(r));
    lowest = std::min(lowest, part(r));
  }
  const double got_max = comm->reducer().max(part(me));
  const double got_min = comm->reducer().min(part(me));
  EXPECT_EQ(got_max, highest);
  EXPECT_EQ(got_min, lowest);
  // Infinite parts (an empty process's maximum is -inf).
  const double max_of_empty = comm->reducer().max(me == n - 1 ? 2.5 : -inf);
  EXPECT_EQ(max_of_empty, 2.5);
}

TEST(Reducer, NanAndSignedZeroGiveTheSameBitsEverywhere) {
  NEEDS_PROCESSES();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double max_nan = comm->reducer().max(me == n - 1 ? nan : 1.0 * me);
  const double min_nan = comm->reducer().min(me == n - 1 ? nan : 1.0 * me);
  // Rank 0 gives +0, the others -0: +0 is the maximum, -0 the minimum (with one process, +0 both).
  const double max_zero = comm->reducer().max(me == 0 ? 0.0 : -0.0);
  const double min_zero = comm->reducer().min(me == 0 ? 0.0 : -0.0);
  EXPECT_TRUE(std::isnan(max_nan));
  EXPECT_TRUE(std::isnan(min_nan));
  EXPECT_EQ(max_zero, 0.0);
  EXPECT_FALSE(std::signbit(max_zero));
  EXPECT_EQ(min_zero, 0.0);
  EXPECT_EQ(std::signbit(min_zero), n > 1);
}

TEST(Reducer, ElementWiseMaxOfVectors) {
  NEEDS_PROCESSES();
  auto part = [](int r) {
    std::vector<double> v(7);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>((3 * i + 5 * r) % 7) - 0.5 * r;
    v[6] = r == 1 ? 4.0 : -inf;  // an entry that one process alone has
    return v;
  };
  std::vector<double> expected = part(0);
  for (int r = 1; r < n; ++r)
    for (std::size_t i = 0; i < expected.size(); ++i) expected[i] = std::max(expected[i], part(r)[i]);
  const std::vector<double> got = comm->reducer().max(part(me));
  EXPECT_EQ(got, expected);
  const std::vector<double> empty = comm->reducer().max(std::vector<double>{});
  EXPECT_TRUE(empty.empty());
}

TEST(Reducer, MaxOfVectorsOfDifferentLengthsThrowsEverywhere) {
  NEEDS_PROCESSES();
  if (n == 1) GTEST_SKIP() << "needs 2 processes";
  bool threw = false;
  try {
    (void)comm->reducer().max(std::vector<double>(static_cast<std::size_t>(3 + me), 1.0));
  } catch (const std::invalid_argument& e) {
    threw = true;
    EXPECT_NE(std::string(e.what()).find("expected the same length on all"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(threw);
}

TEST(Reducer, PayloadOfMaxTiesToTheLowestRank) {
  NEEDS_PROCESSES();
  // Processes 1 and n-1 share the largest value: process 1's payload wins. Payloads have different
  // lengths on every process.
  auto value = [n](int r) { return (r == 1 || r == n - 1) ? 5.0 : 0.1 * r; };
  auto payload = [](int r) {
    std::vector<double> p(static_cast<std::size_t>(r + 1));
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = 100.0 * r + static_cast<double>(i);
    return p;
  };
  const int winner = n >= 2 ? 1 : 0;
  const std::vector<double> got = comm->reducer().payload_of_max(value(me), payload(me));
  EXPECT_EQ(got, payload(winner));

  // The winner's payload is empty; the others' are not.
  const std::vector<double> empty =
      comm->reducer().payload_of_max(me == n - 1 ? 1.0 : 0.0, me == n - 1 ? std::vector<double>{} : payload(me));
  EXPECT_TRUE(empty.empty());

  // NaN counts as the largest value (a run that blew up shows it).
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> with_nan = comm->reducer().payload_of_max(me == n - 1 ? nan : 1e300, payload(me));
  EXPECT_EQ(with_nan, payload(n - 1));
}

// ---- Messages ----

// What process `from` sends to process `to`: tagged, of a length depending on both, with zero bytes,
// and empty for one pair in three.
std::string message(int from, int to) {
  if ((from + 2 * to) % 3 == 0) return {};
  std::string m = "from " + std::to_string(from) + " to " + std::to_string(to) + ":";
  m.append(static_cast<std::size_t>((5 * from + 3 * to) % 11), '\0');
  m.append(static_cast<std::size_t>(from + 1), static_cast<char>('a' + to));
  return m;
}

TEST(Exchange, DeliversEachPartToItsProcess) {
  NEEDS_PROCESSES();
  std::vector<std::string> send(static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) send[static_cast<std::size_t>(r)] = message(me, r);
  const std::vector<std::string> received = comm->exchange(send);
  ASSERT_EQ(received.size(), static_cast<std::size_t>(n));
  for (int r = 0; r < n; ++r) EXPECT_EQ(received[static_cast<std::size_t>(r)], message(r, me)) << "from " << r;
}

TEST(Exchange, NothingToSend) {
  NEEDS_PROCESSES();
  const std::vector<std::string> received = comm->exchange(std::vector<std::string>(static_cast<std::size_t>(n)));
  ASSERT_EQ(received.size(), static_cast<std::size_t>(n));
  for (const std::string& r : received) EXPECT_TRUE(r.empty());
}

TEST(Exchange, WrongNumberOfPartsThrows) {
  NEEDS_PROCESSES();
  // Thrown before any message, on every process alike here.
  EXPECT_THROW((void)comm->exchange(std::vector<std::string>(static_cast<std::size_t>(n + 1))), std::invalid_argument);
}

// ---- Failures ----

// A process that fails between collective calls reports it (fail); the others, waiting in their next
// collective call, throw ProcessFailure with its message instead; then all go on together.
TEST(Failure, TheOthersLearnOfItInTheirNextCollectiveCall) {
  NEEDS_PROCESSES();
  if (n < 2) GTEST_SKIP() << "needs 2 processes";
  const int failing = n - 1;
  sluice::Failure seen;
  if (me == failing) {
    seen = comm->fail("out of memory here", 7);
  } else {
    try {
      (void)comm->exchange(std::vector<std::string>(static_cast<std::size_t>(n), "x"));
      ADD_FAILURE() << "the exchange went ahead";
    } catch (const sluice::ProcessFailure& e) {
      seen = e.failure();
      EXPECT_EQ(std::string(e.what()), "process " + std::to_string(failing) + " of " + std::to_string(n) +
                                           ": out of memory here");
    }
  }
  EXPECT_EQ(seen.process, failing);
  EXPECT_EQ(seen.processes, n);
  EXPECT_EQ(seen.kind, 7);
  EXPECT_EQ(seen.message, "out of memory here");
  // Every process is past the failure at the same point: the next calls match.
  EXPECT_EQ(comm->reducer().sum(std::int64_t{1}), n);
}

// Processes that fail together: every one receives the first's failure, in every kind of call.
TEST(Failure, SeveralAtOnceGiveTheFirstsAndEveryCallChecks) {
  NEEDS_PROCESSES();
  for (int call = 0; call < 5; ++call) {
    const bool fails = me % 2 == 1 || n == 1;
    sluice::Failure seen;
    if (fails) {
      seen = comm->fail("failure of process " + std::to_string(me), me);
    } else {
      try {
        switch (call) {
          case 0: (void)comm->reducer().max(1.0); break;
          case 1: (void)comm->reducer().sum(1.0); break;
          case 2: (void)comm->gather("part"); break;
          case 3: (void)comm->broadcast("root"); break;
          default: (void)comm->partition(2, Points{{0.0, 0.0, 0.0}}, {1.0}); break;
        }
        ADD_FAILURE() << "call " << call << " went ahead";
      } catch (const sluice::ProcessFailure& e) {
        seen = e.failure();
      }
    }
    const int first = n == 1 ? 0 : 1;
    EXPECT_EQ(seen.process, first) << "call " << call;
    EXPECT_EQ(seen.kind, first) << "call " << call;
    EXPECT_EQ(seen.message, "failure of process " + std::to_string(first)) << "call " << call;
  }
  EXPECT_EQ(comm->reducer().sum(std::int64_t{1}), n);
}

TEST(Gather, RootReceivesThePartsInRankOrder) {
  NEEDS_PROCESSES();
  auto part = [](int r) { return r == 1 ? std::string() : message(r, 0) + std::string(1, '\0') + "end"; };
  const std::vector<std::string> got = comm->gather(part(me));
  if (me == 0) {
    ASSERT_EQ(got.size(), static_cast<std::size_t>(n));
    for (int r = 0; r < n; ++r) EXPECT_EQ(got[static_cast<std::size_t>(r)], part(r)) << "part of " << r;
  } else {
    EXPECT_TRUE(got.empty());
  }
}

TEST(Broadcast, EveryProcessReceivesTheRootsBytes) {
  NEEDS_PROCESSES();
  const std::string root_bytes = std::string("root\0bytes", 10) + std::string(1000, 'x');
  const std::string got = comm->broadcast(me == 0 ? root_bytes : "ignored on process " + std::to_string(me));
  EXPECT_EQ(got, root_bytes);
  const std::string empty = comm->broadcast(me == 0 ? std::string() : std::string("not empty"));
  EXPECT_TRUE(empty.empty());
}

// Parts beyond INT_MAX bytes: an exception on every process, before anything is sent. On 2 processes
// only (the code is the same for any number): the 2 GiB part takes seconds to write on a busy machine.
TEST(Messages, BeyondIntMaxBytesThrowEverywhere) {
  NEEDS_PROCESSES();
  if (n != 2) GTEST_SKIP() << "runs on 2 processes";
  std::string big = me == 0 ? std::string(std::size_t{INT_MAX} + 1, 'b') : std::string();
  int length_errors = 0;
  auto count = [&](auto&& call) {
    try {
      call();
    } catch (const std::length_error& e) {
      ++length_errors;
      EXPECT_NE(std::string(e.what()).find("at most 2147483647"), std::string::npos) << e.what();
    }
  };
  count([&] { (void)comm->broadcast(big); });
  count([&] { (void)comm->gather(big); });
  std::vector<std::string> send(2);
  send[1] = std::move(big);  // from process 0 to process 1 (process 1 sends nothing)
  count([&] { (void)comm->exchange(send); });
  EXPECT_EQ(length_errors, 3);
  // The processes are still in step.
  EXPECT_EQ(comm->reducer().sum(std::int64_t{1}), n);
}

// ---- Domain boxes ----

bool inside(const DomainBox& box, const std::array<double, 3>& p, int dimension) {
  for (std::size_t d = 0; d < static_cast<std::size_t>(dimension); ++d)
    if (!(box.lower[d] <= p[d] && p[d] < box.upper[d])) return false;
  return true;
}

// The boxes that hold the point (lower <= x < upper).
std::vector<int> owners(const std::vector<DomainBox>& boxes, const std::array<double, 3>& p, int dimension) {
  std::vector<int> found;
  for (std::size_t b = 0; b < boxes.size(); ++b)
    if (inside(boxes[b], p, dimension)) found.push_back(static_cast<int>(b));
  return found;
}

// The boxes tile space: whether a point is in a box depends only on how its coordinates compare with
// the faces, so one point per class of comparisons (every face value, every gap between two and
// beyond the last) checks every point of space.
void expect_tiling(const std::vector<DomainBox>& boxes, int dimension) {
  std::vector<std::vector<double>> candidates(3);
  for (std::size_t d = 0; d < static_cast<std::size_t>(dimension); ++d) {
    std::vector<double> faces;
    for (const DomainBox& b : boxes)
      for (double f : {b.lower[d], b.upper[d]})
        if (std::isfinite(f)) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    if (faces.empty()) {
      candidates[d] = {0.0};
      continue;
    }
    candidates[d] = {-1e300, 1e300};
    for (std::size_t i = 0; i < faces.size(); ++i) {
      candidates[d].push_back(faces[i]);
      if (i + 1 < faces.size()) candidates[d].push_back(faces[i] + 0.5 * (faces[i + 1] - faces[i]));
    }
  }
  if (dimension == 2) candidates[2] = {0.0};
  int bad = 0;
  for (double x : candidates[0])
    for (double y : candidates[1])
      for (double z : candidates[2]) {
        const std::array<double, 3> p{x, y, z};
        const std::vector<int> in = owners(boxes, p, dimension);
        if (in.size() != 1 && ++bad <= 5)
          ADD_FAILURE() << "point (" << x << ", " << y << ", " << z << ") is in " << in.size() << " boxes";
      }
  EXPECT_EQ(bad, 0);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    for (std::size_t d = 0; d < 3; ++d) {
      EXPECT_FALSE(std::isnan(boxes[b].lower[d]) || std::isnan(boxes[b].upper[d])) << "box " << b;
      EXPECT_LE(boxes[b].lower[d], boxes[b].upper[d]) << "box " << b << " component " << d;
    }
    // The third component of a 2D run is all of it.
    if (dimension == 2) {
      EXPECT_EQ(boxes[b].lower[2], -inf);
      EXPECT_EQ(boxes[b].upper[2], inf);
    }
  }
}

std::string bytes_of(const std::vector<DomainBox>& boxes) {
  std::string bytes(boxes.size() * sizeof(DomainBox), '\0');
  if (!boxes.empty()) std::memcpy(bytes.data(), boxes.data(), bytes.size());
  return bytes;
}

// Every process got the same boxes (the same bits), one per process.
void expect_same_everywhere(const std::vector<DomainBox>& boxes) {
  EXPECT_EQ(boxes.size(), static_cast<std::size_t>(comm->size()));
  const std::string mine = bytes_of(boxes);
  const std::string root = comm->broadcast(mine);
  EXPECT_TRUE(mine == root) << "process " << comm->rank() << " got other boxes than process 0";
}

// The total weight of the points in each box, over all processes.
std::vector<double> weight_per_box(const std::vector<DomainBox>& boxes, const Points& points,
                                   const std::vector<double>& weights, int dimension) {
  std::vector<double> mine(boxes.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::vector<int> in = owners(boxes, points[i], dimension);
    if (in.size() == 1) mine[static_cast<std::size_t>(in[0])] += weights[i];
  }
  std::vector<double> all(boxes.size());
  for (std::size_t b = 0; b < boxes.size(); ++b) all[b] = comm->reducer().sum(mine[b]);
  return all;
}

// Every point of every process is in exactly one box.
void expect_every_point_in_one_box(const std::vector<DomainBox>& boxes, const Points& points, int dimension) {
  std::int64_t bad = 0;
  for (const auto& p : points) bad += owners(boxes, p, dimension).size() != 1;
  EXPECT_EQ(comm->reducer().sum(bad), 0);
}

// Every process's boxes from comm->partition, checked: the same on every process, tiling space,
// every point in exactly one.
std::vector<DomainBox> checked_partition(int dimension, const Points& points, const std::vector<double>& weights) {
  const std::vector<DomainBox> boxes = comm->partition(dimension, points, weights);
  expect_same_everywhere(boxes);
  expect_tiling(boxes, dimension);
  expect_every_point_in_one_box(boxes, points, dimension);
  return boxes;
}

// Each box holds the total weight / processes, within `tolerance` of it.
void expect_balanced(const std::vector<double>& per_box, double tolerance) {
  double total = 0.0;
  for (double w : per_box) total += w;
  const double share = total / static_cast<double>(per_box.size());
  for (std::size_t b = 0; b < per_box.size(); ++b)
    EXPECT_NEAR(per_box[b], share, tolerance * share) << "box " << b << " of " << per_box.size();
}

Points uniform_cloud(std::size_t count, unsigned seed, std::array<double, 3> size = {1.0, 1.0, 1.0}) {
  std::mt19937_64 random(seed * 1000003u + static_cast<unsigned>(comm->rank()));
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Points points(count);
  for (auto& p : points)
    for (std::size_t d = 0; d < 3; ++d) p[d] = size[d] * unit(random);
  return points;
}

// Balanced to 1 % of a box's share: RCB's median search balances each cut to within a point or
// two, far below this with 20000 points per process.
constexpr double balance_tolerance = 0.01;

TEST(Partition, UniformCloud3D) {
  NEEDS_PROCESSES();
  const Points points = uniform_cloud(20000, 1);
  const std::vector<double> weights(points.size(), 1.0);
  const std::vector<DomainBox> boxes = checked_partition(3, points, weights);
  expect_balanced(weight_per_box(boxes, points, weights, 3), balance_tolerance);
}

TEST(Partition, UniformCloud2DIgnoresTheThirdComponent) {
  NEEDS_PROCESSES();
  Points points = uniform_cloud(20000, 2, {2.0, 1.0, 1.0});
  for (auto& p : points) p[2] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> weights(points.size(), 1.0);
  const std::vector<DomainBox> boxes = checked_partition(2, points, weights);
  expect_balanced(weight_per_box(boxes, points, weights, 2), balance_tolerance);
}

TEST(Partition, SkewedCloud) {
  NEEDS_PROCESSES();
  // 90 % of the points in a corner of 5 % of the side, the rest over the whole cube.
  Points points = uniform_cloud(20000, 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (i % 10 != 0)
      for (auto& x : points[i]) x *= 0.05;
  const std::vector<double> weights(points.size(), 1.0);
  for (int dimension : {2, 3}) {
    const std::vector<DomainBox> boxes = checked_partition(dimension, points, weights);
    expect_balanced(weight_per_box(boxes, points, weights, dimension), balance_tolerance);
  }
}

TEST(Partition, BalancesWeightNotCount) {
  NEEDS_PROCESSES();
  // Long in x, so that the cuts are across x; the points at x < 1 weigh 10, the others 1.
  const Points points = uniform_cloud(20000, 4, {4.0, 1.0, 1.0});
  std::vector<double> weights(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) weights[i] = points[i][0] < 1.0 ? 10.0 : 1.0;
  const std::vector<double> ones(points.size(), 1.0);
  for (int dimension : {2, 3}) {
    const std::vector<DomainBox> boxes = checked_partition(dimension, points, weights);
    expect_balanced(weight_per_box(boxes, points, weights, dimension), balance_tolerance);
    if (n > 1) {
      const std::vector<double> counts = weight_per_box(boxes, points, ones, dimension);
      const auto [fewest, most] = std::minmax_element(counts.begin(), counts.end());
      EXPECT_GT(*most, 1.5 * *fewest) << "the counts are balanced, not the weights";
    }
  }
}

TEST(Partition, ProcessesWithoutPoints) {
  NEEDS_PROCESSES();
  // All the points on process 0, then none on the last process.
  for (int empty_from : {1, n - 1}) {
    const Points points = me < std::max(empty_from, 1) ? uniform_cloud(30000, 5) : Points{};
    const std::vector<double> weights(points.size(), 1.0);
    const std::vector<DomainBox> boxes = checked_partition(3, points, weights);
    expect_balanced(weight_per_box(boxes, points, weights, 3), balance_tolerance);
  }
}

TEST(Partition, PointOnASharedFaceBelongsToTheBoxAbove) {
  NEEDS_PROCESSES();
  const Points cloud = uniform_cloud(5000, 6);
  const std::vector<double> weights(cloud.size(), 1.0);
  const std::vector<DomainBox> boxes = comm->partition(3, cloud, weights);
  expect_same_everywhere(boxes);
  // A point inside box b in every component but one, where it is on b's lower face: b holds it; on
  // b's upper face: b does not (the box above does).
  auto middle = [](double lo, double hi) {
    if (std::isinf(lo) && std::isinf(hi)) return 0.5;
    if (std::isinf(lo)) return hi - 1.0;
    if (std::isinf(hi)) return lo + 1.0;
    return lo + 0.5 * (hi - lo);
  };
  int faces = 0;
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    std::array<double, 3> centre{};
    for (std::size_t d = 0; d < 3; ++d) centre[d] = middle(boxes[b].lower[d], boxes[b].upper[d]);
    for (std::size_t d = 0; d < 3; ++d) {
      if (std::isfinite(boxes[b].lower[d])) {
        std::array<double, 3> p = centre;
        p[d] = boxes[b].lower[d];
        const std::vector<int> in = owners(boxes, p, 3);
        EXPECT_EQ(in, std::vector<int>{static_cast<int>(b)}) << "lower face " << d << " of box " << b;
        ++faces;
      }
      if (std::isfinite(boxes[b].upper[d])) {
        std::array<double, 3> p = centre;
        p[d] = boxes[b].upper[d];
        const std::vector<int> in = owners(boxes, p, 3);
        EXPECT_EQ(in.size(), 1u) << "upper face " << d << " of box " << b;
        if (in.size() == 1) {
          EXPECT_NE(in[0], static_cast<int>(b)) << "upper face " << d << " of box " << b;
          EXPECT_EQ(boxes[static_cast<std::size_t>(in[0])].lower[d], boxes[b].upper[d])
              << "the box above shares the exact cut value";
        }
        ++faces;
      }
    }
  }
  EXPECT_EQ(faces > 0, n > 1);
  // The cloud again with points moved exactly onto the cut values, and at corners of several cuts.
  Points on_cuts = cloud;
  std::vector<double> cuts;
  for (const DomainBox& b : boxes)
    for (std::size_t d = 0; d < 3; ++d)
      if (std::isfinite(b.lower[d])) cuts.push_back(b.lower[d]);
  for (std::size_t i = 0; i < on_cuts.size() && !cuts.empty(); ++i)
    for (std::size_t d = 0; d < 3; ++d)
      if ((i + d) % 2 == 0) on_cuts[i][d] = cuts[(i * 7 + d) % cuts.size()];
  expect_every_point_in_one_box(boxes, on_cuts, 3);
}

// A lattice, as the particles of a run start: the cuts fall between two rows, never on a point, and
// every box is within one row per cut of its share.
TEST(Partition, LatticeIsCutBetweenItsRows) {
  NEEDS_PROCESSES();
  for (int dimension : {2, 3}) {
    const std::array<int, 3> cells = dimension == 2 ? std::array<int, 3>{60, 40, 1} : std::array<int, 3>{20, 15, 10};
    Points points;  // dealt round-robin to the processes
    int index = 0;
    for (int i = 0; i < cells[0]; ++i)
      for (int j = 0; j < cells[1]; ++j)
        for (int k = 0; k < cells[2]; ++k, ++index)
          if (index % n == me) points.push_back({0.1 * i, 0.1 * j, dimension == 2 ? 0.0 : 0.1 * k});
    const std::vector<double> weights(points.size(), 1.0);
    const std::vector<DomainBox> boxes = comm->partition(dimension, points, weights);
    expect_same_everywhere(boxes);
    expect_tiling(boxes, dimension);
    std::int64_t on_faces = 0;
    for (const auto& p : points)
      for (const DomainBox& b : boxes)
        for (std::size_t d = 0; d < static_cast<std::size_t>(dimension); ++d)
          on_faces += p[d] == b.lower[d] || p[d] == b.upper[d];
    EXPECT_EQ(comm->reducer().sum(on_faces), 0) << "points on faces, in " << dimension << "D";
    // A row has at most (largest cross-section) points; there are at most log2(n) + 1 levels of cuts.
    const int row = dimension == 2 ? cells[0] : cells[0] * cells[1];
    const int levels = n <= 1 ? 0 : n <= 2 ? 1 : 2;
    const std::vector<double> per_box = weight_per_box(boxes, points, weights, dimension);
    const double share = cells[0] * cells[1] * cells[2] / static_cast<double>(n);
    for (std::size_t b = 0; b < per_box.size(); ++b)
      EXPECT_NEAR(per_box[b], share, levels * row) << "box " << b << " in " << dimension << "D";
  }
}

TEST(Partition, Deterministic) {
  NEEDS_PROCESSES();
  const Points points = uniform_cloud(10000, 7);
  std::vector<double> weights(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) weights[i] = 1.0 + static_cast<double>(i % 3);
  const std::vector<DomainBox> first = comm->partition(3, points, weights);
  const std::vector<DomainBox> second = comm->partition(3, points, weights);
  EXPECT_TRUE(bytes_of(first) == bytes_of(second)) << "two calls gave different boxes";
}

TEST(Partition, AllPointsIdentical) {
  NEEDS_PROCESSES();
  const Points points(100, {0.3, -2.0, 7.0});
  const std::vector<double> weights(points.size(), 1.0);
  for (int dimension : {2, 3}) {
    const std::vector<DomainBox> boxes = checked_partition(dimension, points, weights);
  }
}

TEST(Partition, ClumpThatCannotBeSplitBesideACloud) {
  NEEDS_PROCESSES();
  // Two thirds of the points on one spot inside the cloud of the others: the processes that share the
  // clump cannot split it, and their boxes must still tile space (Zoltan's own boxes overlap here on
  // 6 processes or more: see tiling_boxes in mpi_communicator.cpp).
  Points points = uniform_cloud(300, 12, {1.0, 1.0, 1.0});
  for (std::size_t i = 0; i < points.size(); ++i)
    if (i % 3 != 0) points[i] = {0.0, 0.75, 0.75};
  const std::vector<double> weights(points.size(), 1.0);
  for (int dimension : {2, 3}) {
    const std::vector<DomainBox> boxes = checked_partition(dimension, points, weights);
  }
}

TEST(Partition, AllWeightsZeroCountEveryPointAsOne) {
  NEEDS_PROCESSES();
  const Points points = uniform_cloud(20000, 8);
  const std::vector<double> zeros(points.size(), 0.0), ones(points.size(), 1.0);
  const std::vector<DomainBox> boxes = comm->partition(3, points, zeros);
  expect_same_everywhere(boxes);
  expect_tiling(boxes, 3);
  expect_balanced(weight_per_box(boxes, points, ones, 3), balance_tolerance);
}

TEST(Partition, FewerPointsThanProcesses) {
  NEEDS_PROCESSES();
  const Points points = me == 0 ? Points{{0.5, 0.5, 0.5}} : Points{};
  const std::vector<double> weights(points.size(), 1.0);
  const std::vector<DomainBox> boxes = checked_partition(3, points, weights);
}

TEST(Partition, NoPointsAnywhere) {
  NEEDS_PROCESSES();
  const std::vector<DomainBox> boxes = comm->partition(3, Points{}, std::vector<double>{});
  expect_same_everywhere(boxes);
  expect_tiling(boxes, 3);
  EXPECT_EQ(owners(boxes, {1.0, 2.0, 3.0}, 3), std::vector<int>{0});
}

TEST(Partition, OneProcessOwnsAllOfSpace) {
  NEEDS_PROCESSES();
  if (n != 1) GTEST_SKIP() << "runs on one process";
  const Points points = uniform_cloud(100, 9);
  const std::vector<DomainBox> boxes = comm->partition(3, points, std::vector<double>(points.size(), 1.0));
  ASSERT_EQ(boxes.size(), 1u);
  for (std::size_t d = 0; d < 3; ++d) {
    EXPECT_EQ(boxes[0].lower[d], -inf);
    EXPECT_EQ(boxes[0].upper[d], inf);
  }
}

// Invalid input on one process: the same exception on every process, naming it.
void expect_invalid_everywhere(int dimension, const Points& points, const std::vector<double>& weights,
                               const std::string& expected_text) {
  std::string what;
  try {
    (void)comm->partition(dimension, points, weights);
  } catch (const std::invalid_argument& e) {
    what = e.what();
  }
  EXPECT_NE(what.find(expected_text), std::string::npos) << "message: '" << what << "'";
  EXPECT_EQ(comm->broadcast(what), what) << "another message on process 0";
}

TEST(Partition, InvalidInputThrowsOnEveryProcess) {
  NEEDS_PROCESSES();
  const int last = n - 1;
  const std::string on_last = "on process " + std::to_string(last);
  Points points = uniform_cloud(50, 10);
  std::vector<double> weights(points.size(), 1.0);

  Points with_nan = points;
  if (me == last) with_nan[7][1] = std::numeric_limits<double>::quiet_NaN();
  expect_invalid_everywhere(3, with_nan, weights, "point 7 " + on_last + " has coordinate 1 = nan");

  Points with_huge = points;
  if (me == last) with_huge[2][0] = 2e300;
  expect_invalid_everywhere(3, with_huge, weights, "point 2 " + on_last + " has coordinate 0 = 2e+300");

  std::vector<double> negative = weights;
  if (me == last) negative[3] = -1.0;
  expect_invalid_everywhere(3, points, negative, "point 3 " + on_last + " has weight -1");

  std::vector<double> short_weights = weights;
  if (me == last) short_weights.pop_back();
  expect_invalid_everywhere(3, points, short_weights, "49 weights for 50 points " + on_last);

  expect_invalid_everywhere(me == last ? 4 : 3, points, weights, "dimension 4 " + on_last + "; expected 2 or 3");

  if (n > 1) expect_invalid_everywhere(me == 0 ? 2 : 3, points, weights, "dimension 2 on some processes and 3");

  // And the processes still work together afterwards.
  const std::vector<DomainBox> boxes = comm->partition(3, points, weights);
  expect_tiling(boxes, 3);
}

// Standard output into a temporary file for the life of this object (on every process, even if the
// file could not be made: the calls inside are collective).
class CapturedStandardOutput {
 public:
  CapturedStandardOutput() : saved_(::dup(STDOUT_FILENO)), file_(std::tmpfile()) {
    std::fflush(stdout);
    if (file_ != nullptr) ::dup2(::fileno(file_), STDOUT_FILENO);
  }
  ~CapturedStandardOutput() {
    restore();
    if (file_ != nullptr) std::fclose(file_);
  }
  CapturedStandardOutput(const CapturedStandardOutput&) = delete;
  CapturedStandardOutput& operator=(const CapturedStandardOutput&) = delete;
  // The bytes written, or -1 without a file; standard output is back from here on.
  long bytes() {
    restore();
    return file_ != nullptr ? static_cast<long>(::lseek(::fileno(file_), 0, SEEK_END)) : -1;
  }

 private:
  void restore() {
    if (saved_ < 0) return;
    std::fflush(stdout);
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
    saved_ = -1;
  }
  int saved_;
  std::FILE* file_;
};

TEST(Partition, WritesNothingOnStandardOutput) {
  NEEDS_PROCESSES();
  const Points points = uniform_cloud(2000, 11);
  const std::vector<double> weights(points.size(), 1.0);
  std::vector<DomainBox> boxes;
  long written = 0;
  {
    CapturedStandardOutput captured;
    boxes = comm->partition(3, points, weights);
    (void)comm->partition(2, Points(10, {1.0, 1.0, 1.0}), std::vector<double>(10, 0.0));
    written = captured.bytes();
  }
  EXPECT_EQ(written, 0) << "Zoltan wrote on standard output (-1: no temporary file)";
  expect_tiling(boxes, 3);
}

// ---- Output and exit status ----

// The other ranks print their failures only, marked with their rank.
class FailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit FailurePrinter(int rank) : rank_(rank) {}
  void OnTestStart(const ::testing::TestInfo& test) override {
    name_ = std::string(test.test_suite_name()) + "." + test.name();
  }
  void OnTestPartResult(const ::testing::TestPartResult& result) override {
    if (!result.failed()) return;
    std::fprintf(stderr, "[process %d] %s: %s:%d: failure\n%s\n", rank_, name_.c_str(),
                 result.file_name() != nullptr ? result.file_name() : "?", result.line_number(), result.summary());
    std::fflush(stderr);
  }

 private:
  int rank_;
  std::string name_;
};

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<sluice::MpiSession> mpi;
  try {
    mpi = sluice::start_mpi_if_launched(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "test_mpi_communicator: %s\n", e.what());
    return 1;
  }
  session = mpi.get();
  // mpiexec gives the processes a terminal, whose colours would end up in ctest's log.
  if (mpi != nullptr) GTEST_FLAG_SET(color, "no");
  ::testing::InitGoogleTest(&argc, argv);
  // Under mpiexec -np 1 the session has no communicator (the solver runs serially); the tests use one
  // of a single process.
  std::unique_ptr<sluice::MpiCommunicator> single;
  if (mpi != nullptr) {
    comm = mpi->world();
    if (comm == nullptr) {
      single = std::make_unique<sluice::MpiCommunicator>();
      comm = single.get();
    }
  }

  // tests/test_mpi_abort.sh: the last process stops the run while the others wait for it.
  if (argc > 1 && std::string(argv[1]) == "--sluice-test-abort") {
    if (comm == nullptr) return 2;
    if (comm->rank() == comm->size() - 1)
      comm->abort("stopped on purpose by process " + std::to_string(comm->rank()), 3);
    (void)comm->reducer().sum(std::int64_t{1});
    return 1;  // not reached: the abort stops this process too
  }

  if (mpi != nullptr) {
    if (mpi->rank() == 0) {
      std::printf("MPI_Init_thread took %.3f s (%d processes)\n", mpi->init_seconds(), mpi->size());
    } else {
      ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
      delete listeners.Release(listeners.default_result_printer());
      listeners.Append(new FailurePrinter(mpi->rank()));
    }
  }
  const int result = RUN_ALL_TESTS();
  if (comm == nullptr) return result;
  // A failure on any process fails them all.
  const std::int64_t failed = comm->reducer().sum(std::int64_t{result != 0});
  single.reset();
  if (failed != 0 && mpi->rank() == 0)
    std::printf("%lld of %d processes failed\n", static_cast<long long>(failed), mpi->size());
  return failed == 0 ? 0 : 1;
}
