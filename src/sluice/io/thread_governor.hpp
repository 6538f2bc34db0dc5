// How many of its threads a run steps with. More threads are faster on a quiet machine, but when
// another process keeps a core busy a thread of the run waits for that core at every barrier of the
// step, and fewer threads are faster (on two cores with one busy loop beside, the 20k-particle dam
// break takes about 1.3 times as long on two threads as on one). Threads that spin while they wait
// make that worse still, and threads that sleep cost a wake-up at every parallel loop of a quiet
// machine. So the run measures instead: it steps with all its threads, now and then steps a
// short window with half as many (or, after it came down, twice as many), and keeps whichever was
// faster. The results are the same bits on any thread count, so the choice changes only the speed.
//
// The windows are counted in steps, and their times are the largest over the run's processes, so
// that every process of an MPI run decides alike at the same steps.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace sluice {

class ThreadGovernor {
 public:
  // Up to `max_threads` threads (exactly that many when `adapt` is false); `max_over_processes` gives
  // the largest of a value over the run's processes (the value itself for one process) and is called
  // at the same steps on every process.
  ThreadGovernor(int max_threads, bool adapt, std::function<double(double)> max_over_processes);

  // The thread count for the next step.
  [[nodiscard]] int threads() const { return levels_[static_cast<std::size_t>(trying_)]; }
  // After a step at threads() that took `seconds` of wall time.
  void stepped(double seconds);

  // Steps taken at each thread count so far (for the summary), most threads first.
  struct Share {
    int threads;
    std::int64_t steps;
  };
  [[nodiscard]] std::vector<Share> shares() const;

 private:
  enum class Phase { hold, measure_current, measure_probe };
  void start(Phase phase, std::int64_t steps);
  void decide(double current_per_step, double probe_per_step);

  std::function<double(double)> max_over_processes_;
  std::vector<int> levels_;  // the thread counts tried: max, max/2, ..., 1
  std::vector<std::int64_t> steps_at_;
  int current_ = 0;          // index of the count the run keeps
  int trying_ = 0;           // index of the count of the next step
  int probe_ = 0;            // index of the count the probe window measures
  bool probe_down_next_ = true;
  Phase phase_ = Phase::hold;
  std::int64_t left_ = 0;    // steps left in this phase
  std::int64_t length_ = 0;  // steps in this phase
  double seconds_ = 0.0;     // wall time of this phase's steps so far
  double per_step_ = 0.0;    // the last measured time of a step at the current count
  double current_per_step_ = 0.0;
  double hold_seconds_ = 0.0;
};

}  // namespace sluice
