// When a run writes its frames and checkpoints, and when it stops. Frames land exactly on the times
// k * output.interval (computed as static_cast<double>(k) * interval), checkpoints on
// k * output.checkpoint_interval; a step that would pass one of them is cut to end on it.
#pragma once

#include <cstdint>

#include "sluice/case/case.hpp"

namespace sluice {

// Index of the first time k * interval strictly after t. Exact, so that a restart finds the same next
// frame and checkpoint times as the run that never stopped.
[[nodiscard]] std::int64_t next_index_after(double t, double interval);

// The time a run of `c` stops at: time.end, or the frame or checkpoint time within rounding of it
// (3 * 0.1 = 0.30000000000000004, so that a run with `time.end = 0.3` stops exactly where a longer run
// writes its frame, and a restart from its checkpoint continues that longer run bit for bit).
[[nodiscard]] double stop_time(const Case& c);

// The frames a run of `c` from time t to its end writes: one at each output interval, and the last.
[[nodiscard]] double planned_frames(const Case& c, double t);

// The next frame and checkpoint, as indices k of the times k * interval, and the time the run stops at.
class Schedule {
 public:
  Schedule(const Case& c, double t);

  [[nodiscard]] double end() const { return end_; }
  [[nodiscard]] std::int64_t next_frame() const { return next_frame_; }

  // The time the next step must end on if it would pass it: the next frame, checkpoint or the end.
  [[nodiscard]] double step_limit() const;

  // A frame is due at its time, and at the end (which may fall between frame times).
  [[nodiscard]] bool frame_due(double t) const { return t >= frame_time() || t >= end_; }
  void frame_written(double t) {
    if (t >= frame_time()) ++next_frame_;
  }

  [[nodiscard]] bool checkpoint_due(double t) const { return checkpoint_interval_ > 0 && t >= checkpoint_time(); }
  void checkpoint_written(double t) { next_checkpoint_ = next_index_after(t, checkpoint_interval_); }

 private:
  [[nodiscard]] double frame_time() const { return static_cast<double>(next_frame_) * frame_interval_; }
  [[nodiscard]] double checkpoint_time() const {
    return static_cast<double>(next_checkpoint_) * checkpoint_interval_;
  }

  double frame_interval_;
  double checkpoint_interval_;
  double end_;
  std::int64_t next_frame_;
  std::int64_t next_checkpoint_;
};

}  // namespace sluice
