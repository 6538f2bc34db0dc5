#include "sluice/io/thread_governor.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace sluice {

namespace {

constexpr std::int64_t kWarmUpSteps = 20;  // first steps, slower for reasons of their own (page faults)
constexpr double kWindowSeconds = 0.1;     // a measuring window, at least kWindowSteps steps
constexpr std::int64_t kWindowSteps = 3;
constexpr double kFirstHoldSeconds = 1.0;  // between probes: doubled each time the count stays
constexpr double kLongestHoldSeconds = 120.0;
// Below the most threads: the machine may have become quiet again, and a probe up costs little.
constexpr double kLongestHoldBelowSeconds = 10.0;
// At least this many times a window between probes, so that probing costs a few percent of the run
// at most, also when a step takes seconds (and under 1 % once the holds have grown).
constexpr double kHoldOverWindow = 20.0;
// A probe must be this much faster to be kept: the windows of a shared machine differ by a few
// percent with nothing changed.
constexpr double kMargin = 0.05;

}  // namespace

ThreadGovernor::ThreadGovernor(int max_threads, bool adapt, std::function<double(double)> max_over_processes)
    : max_over_processes_(std::move(max_over_processes)), hold_seconds_(kFirstHoldSeconds) {
  for (int t = std::max(1, max_threads);; t /= 2) {
    levels_.push_back(t);
    if (t == 1 || !adapt) break;
  }
  steps_at_.assign(levels_.size(), 0);
  start(Phase::hold, kWarmUpSteps);
}

void ThreadGovernor::start(Phase phase, std::int64_t steps) {
  phase_ = phase;
  length_ = left_ = std::max<std::int64_t>(1, steps);
  seconds_ = 0.0;
}

void ThreadGovernor::stepped(double seconds) {
  ++steps_at_[static_cast<std::size_t>(trying_)];
  if (levels_.size() == 1) return;  // nothing to choose: no windows, and no calls over the processes
  seconds_ += seconds;
  if (--left_ > 0) return;
  const double per_step = max_over_processes_(seconds_) / static_cast<double>(length_);
  // Steps that take `wall` seconds at the current count.
  const auto steps_for = [&](double wall) { return static_cast<std::int64_t>(std::ceil(wall / per_step_)); };
  switch (phase_) {
    case Phase::hold:
      per_step_ = std::max(per_step, 1e-9);
      start(Phase::measure_current, std::max(kWindowSteps, steps_for(kWindowSeconds)));
      break;
    case Phase::measure_current: {
      current_per_step_ = per_step;
      const bool down = current_ + 1 < static_cast<int>(levels_.size()), up = current_ > 0;
      const bool go_down = down && (!up || probe_down_next_);
      probe_down_next_ = !go_down;
      probe_ = go_down ? current_ + 1 : current_ - 1;
      trying_ = probe_;
      start(Phase::measure_probe, length_);  // as many steps as the window it is compared with
      break;
    }
    case Phase::measure_probe: {
      const double window_seconds = static_cast<double>(length_) * per_step_;
      decide(current_per_step_, per_step);
      trying_ = current_;
      start(Phase::hold, steps_for(std::max(hold_seconds_, kHoldOverWindow * window_seconds)));
      break;
    }
  }
}

void ThreadGovernor::decide(double current_per_step, double probe_per_step) {
  if (probe_per_step < (1.0 - kMargin) * current_per_step) {
    current_ = probe_;
    per_step_ = std::max(probe_per_step, 1e-9);
    hold_seconds_ = kFirstHoldSeconds;
  } else {
    hold_seconds_ = std::min(2.0 * hold_seconds_, current_ == 0 ? kLongestHoldSeconds : kLongestHoldBelowSeconds);
  }
}

std::vector<ThreadGovernor::Share> ThreadGovernor::shares() const {
  std::vector<Share> out;
  for (std::size_t k = 0; k < levels_.size(); ++k)
    if (steps_at_[k] > 0) out.push_back({levels_[k], steps_at_[k]});
  return out;
}

}  // namespace sluice
