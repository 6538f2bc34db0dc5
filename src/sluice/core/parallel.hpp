// Threads for the loops over particles, in one place: the data structures and the solver call these
// instead of writing OpenMP directives, so that the threading model (OpenMP today) can change
// without touching them. Every loop is split statically in index order unless it says otherwise, so
// that results do not depend on how many threads run it.
#pragma once

#include <omp.h>

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

// f(i) for every i in [0, n), handed out `chunk` indices at a time (for loops whose iterations cost
// very different amounts).
template <class F>
void for_each_dynamic(long n, int threads, long chunk, F&& f) {
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads)
  for (long i = 0; i < n; ++i) f(i);
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

// The threads of one parallel region, for work in several phases separated by barriers
// (see in_team). Its members must be reached by every thread of the team.
class Team {
 public:
  [[nodiscard]] int index() const { return omp_get_thread_num(); }
  [[nodiscard]] int size() const { return omp_get_num_threads(); }
  void barrier() const {
#pragma omp barrier
  }
  // g() on one thread, the others waiting at its end.
  template <class G>
  void single(G&& g) const {
#pragma omp single
    g();
  }
};

// f(team) on `threads` threads (one when `parallel` is false).
template <class F>
void in_team(int threads, bool parallel, F&& f) {
#pragma omp parallel num_threads(threads) if (parallel)
  {
    const Team team;
    f(team);
  }
}

}  // namespace sluice::parallel
