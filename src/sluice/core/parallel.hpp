// Threads for the loops over particles, in one place: the data structures and the solver call these
// instead of writing OpenMP directives, so that the threading model (OpenMP today) can change
// without touching them. Every loop is split statically in index order unless it says otherwise, so
// that results do not depend on how many threads run it.
#pragma once

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <vector>

namespace sluice::parallel {

// Light O(N) loops (reordering, per-particle terms, integration) only pay for threads when there are
// enough particles: below this, starting the threads and their barrier cost more than the loop,
// badly so when the machine is busy with other work.
inline constexpr long light_loop_threshold = 20000;

// The neighbour loops (forces, Shepard filter, shifting, wall extrapolation) share out work above
// this many particles. Measured on two cores (the dam break, one thread against two, loop times):
// two threads were slower at 2,161 and 3,365 particles (0.73x and 0.75-0.97x), even at 4,983 (0.94-
// 0.97x), and faster from 6,736 (1.09-1.17x).
inline constexpr long pair_loop_threshold = 6000;

// f(begin, end) on contiguous chunks covering [0, n), one per thread, on `threads` threads when n is
// at least `threshold`. The body can be a straight loop the compiler vectorises.
template <class F>
void for_chunks(long n, int threads, F&& f, long threshold = light_loop_threshold) {
  const int teams = n >= threshold ? (threads > 1 ? threads : 1) : 1;
  if (teams == 1) {
    f(0L, n);
    return;
  }
#pragma omp parallel num_threads(teams)
  {
    const long t = omp_get_thread_num(), size = omp_get_num_threads();
    f(n * t / size, n * (t + 1) / size);
  }
}

// The sum of f(i) over [0, n), for counts (integers, so the order of the sum does not matter).
template <class T, class F>
T count(long n, int threads, F&& f) {
  T total{};
  for_chunks(n, threads, [&](long begin, long end) {
    T part{};
    for (long i = begin; i < end; ++i) part += f(i);
#pragma omp atomic
    total += part;
  });
  return total;
}

// A barrier of the current team, and none in a team of one thread: there libgomp's barrier still
// makes a futex system call, about 16 a step in the loops that run on one thread below
// light_loop_threshold or pair_loop_threshold (7 % of a one-thread run of the default case, in the
// kernel). Every thread of a team takes the same branch.
inline void barrier() {
  if (omp_get_num_threads() > 1) {
#pragma omp barrier
  }
}

// The threads of one parallel region, for work in several phases separated by barriers
// (see in_team). Its members must be reached by every thread of the team.
class Team {
 public:
  [[nodiscard]] int index() const { return omp_get_thread_num(); }
  [[nodiscard]] int size() const { return omp_get_num_threads(); }
  void barrier() const { parallel::barrier(); }
  // g() on one thread, the others waiting at its end.
  template <class G>
  void single(G&& g) const {
    if (size() == 1) {
      g();
      return;
    }
#pragma omp single
    g();
  }
};

// f(team) on `threads` threads (one when `parallel` is false). On one thread, and outside any
// parallel region, it is called directly: a region of one thread still ends in a libgomp barrier,
// with a futex system call.
template <class F>
void in_team(int threads, bool parallel, F&& f) {
  if ((!parallel || threads <= 1) && !omp_in_parallel()) {
    f(Team{});
    return;
  }
#pragma omp parallel num_threads(threads) if (parallel)
  {
    const Team team;
    f(team);
  }
}

// before[i] = how many k < i have f(k), for i in [0, n] (before is resized to n + 1): each thread
// counts its contiguous share, then writes its share from the counts of the shares before it. A
// pass on one thread would bring every particle's cache line to that thread's core, for the other
// threads to fetch back in the next pass.
template <class F>
void prefix_count(long n, int threads, std::vector<std::uint32_t>& before, F&& f) {
  before.resize(static_cast<std::size_t>(n) + 1);
  const int teams = n >= light_loop_threshold ? std::max(1, threads) : 1;
  if (teams == 1) {  // one pass: no other thread's share to count first
    std::uint32_t running = 0;
    for (long i = 0; i < n; ++i) {
      before[static_cast<std::size_t>(i)] = running;
      running += f(i) ? 1u : 0u;
    }
    before[static_cast<std::size_t>(n)] = running;
    return;
  }
  std::vector<std::uint32_t> shares(static_cast<std::size_t>(teams) + 1, 0);
  in_team(teams, teams > 1, [&](const Team& team) {
    const long t = team.index(), size = team.size();
    const long begin = n * t / size, end = n * (t + 1) / size;
    std::uint32_t count = 0;
    for (long i = begin; i < end; ++i) count += f(i) ? 1u : 0u;
    shares[static_cast<std::size_t>(t) + 1] = count;
    team.barrier();
    std::uint32_t running = 0;
    for (long u = 0; u <= t; ++u) running += shares[static_cast<std::size_t>(u)];
    for (long i = begin; i < end; ++i) {
      before[static_cast<std::size_t>(i)] = running;
      running += f(i) ? 1u : 0u;
    }
    if (t == size - 1) before[static_cast<std::size_t>(n)] = running;
  });
}

// Work shared out in contiguous runs, with stealing: each thread takes the items of its own run from
// the front, in order, and when that is empty takes the last item of the run with the most left. A
// thread thus works on neighbouring items (whose data stay in its core's cache from one pass to the
// next) and the threads finish together however uneven the items' costs. Items are first, first +
// stride, ..., last; set() every run before any thread calls next().
class StealingRuns {
 public:
  explicit StealingRuns(int threads) : runs_(static_cast<std::size_t>(std::max(1, threads))) {
    for (auto& run : runs_) run.store(pack(0, -1));  // empty (a team may have fewer threads)
  }
  // Thread t's run: first, first + stride, ..., last (empty if first > last; -2^30 < items < 2^30).
  void set(int t, long first, long last) { runs_[static_cast<std::size_t>(t)].store(pack(first, last)); }
  // Thread t's next item, or -1 when every run is empty.
  long next(int t, long stride) {
    std::atomic<std::uint64_t>& own = runs_[static_cast<std::size_t>(t)];
    for (std::uint64_t v = own.load(); first(v) <= last(v);)
      if (own.compare_exchange_weak(v, pack(first(v) + stride, last(v)))) return first(v);
    for (;;) {
      std::atomic<std::uint64_t>* most = nullptr;
      long most_left = 0;
      for (auto& run : runs_) {
        const std::uint64_t v = run.load();
        if (last(v) - first(v) + 1 > most_left) {
          most_left = last(v) - first(v) + 1;
          most = &run;
        }
      }
      if (most == nullptr) return -1;
      std::uint64_t v = most->load();
      if (first(v) <= last(v) && most->compare_exchange_strong(v, pack(first(v), last(v) - stride))) return last(v);
    }
  }

 private:
  static constexpr long kOffset = 1L << 30;
  static std::uint64_t pack(long first, long last) {
    return (static_cast<std::uint64_t>(first + kOffset) << 32) | static_cast<std::uint64_t>(last + kOffset);
  }
  static long first(std::uint64_t v) { return static_cast<long>(v >> 32) - kOffset; }
  static long last(std::uint64_t v) { return static_cast<long>(v & 0xffffffffu) - kOffset; }
  std::vector<std::atomic<std::uint64_t>> runs_;
};

// f(i) for every i in [0, n), for loops whose iterations cost very different amounts: `chunk` indices
// at a time, each thread taking the chunks of its contiguous share in order and then the last chunks
// of the others' (StealingRuns). Unlike chunks handed out in turn, a thread keeps to its own share
// while there is any, so the particles' cache lines stay with its core.
template <class F>
void for_each_dynamic(long n, int threads, long chunk, F&& f) {
  const long chunks = (n + chunk - 1) / chunk;
  StealingRuns runs(threads);
#pragma omp parallel num_threads(threads)
  {
    const int t = omp_get_thread_num(), size = omp_get_num_threads();
    runs.set(t, chunks * t / size, chunks * (t + 1) / size - 1);
    barrier();
    for (long c = runs.next(t, 1); c >= 0; c = runs.next(t, 1))
      for (long i = c * chunk, end = std::min(n, (c + 1) * chunk); i < end; ++i) f(i);
  }
}

}  // namespace sluice::parallel
