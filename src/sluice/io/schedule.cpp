#include "sluice/io/schedule.hpp"

#include <algorithm>
#include <cmath>

namespace sluice {

std::int64_t next_index_after(double t, double interval) {
  auto k = static_cast<std::int64_t>(std::floor(t / interval)) + 1;
  while (k > 0 && static_cast<double>(k - 1) * interval > t) --k;
  while (static_cast<double>(k) * interval <= t) ++k;
  return k;
}

double stop_time(const Case& c) {
  for (const double interval : {c.output_interval, c.checkpoint_interval}) {
    if (!(interval > 0.0)) continue;
    const double k = std::round(c.end_time / interval);
    const double on_grid = k * interval;
    if (std::abs(on_grid - c.end_time) <= 1e-9 * interval) return on_grid;
  }
  return c.end_time;
}

double planned_frames(const Case& c, double t) {
  return std::floor(std::max(0.0, stop_time(c) - t) / c.output_interval) + 1.0;
}

Schedule::Schedule(const Case& c, double t)
    : frame_interval_(c.output_interval), checkpoint_interval_(c.checkpoint_interval), end_(stop_time(c)),
      next_frame_(next_index_after(t, frame_interval_)),
      next_checkpoint_(checkpoint_interval_ > 0 ? next_index_after(t, checkpoint_interval_) : 0) {}

double Schedule::step_limit() const {
  const double limit = std::min(frame_time(), end_);
  return checkpoint_interval_ > 0 ? std::min(limit, checkpoint_time()) : limit;
}

}  // namespace sluice
