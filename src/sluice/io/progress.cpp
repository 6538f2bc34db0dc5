#include "sluice/io/progress.hpp"

#include <fmt/format.h>

#include <cmath>

namespace sluice {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

ProgressLine::ProgressLine(ProgressMode mode, std::ostream& log, double t_start, double t_end, std::size_t particles)
    : mode_(mode), log_(log), t_start_(t_start), t_end_(t_end), particles_(particles) {}

void ProgressLine::update(const Simulation& sim, std::int64_t steps, double wall, bool force) {
  if (mode_ == ProgressMode::none) return;
  const double t = sim.time();
  if (mode_ == ProgressMode::tty) {
    if (!force && wall - last_wall_ < 0.2) return;
  } else {
    const double every = 0.05 * (t_end_ - t_start_);
    if (!force && t < next_line_t_ && wall - last_wall_ < 30.0) return;
    next_line_t_ = t + every;
  }
  last_wall_ = wall;
  const double rate = wall > 0 ? static_cast<double>(particles_) * static_cast<double>(steps) / wall : 0.0;
  const double eta = t > t_start_ ? wall * (t_end_ - t) / (t - t_start_) : NAN;
  const std::string line =
      fmt::format("t = {:.3f}/{:.3f} s  step {}  dt {:.2e} s  {:.2f} M particle-steps/s  ETA {}", t, t_end_,
                  sim.clock().step, sim.clock().last_dt, rate * 1e-6, format_duration(eta));
  if (mode_ == ProgressMode::tty) log_ << "\r" << line << "\x1b[K" << std::flush;
  else log_ << line << "\n" << std::flush;
}

void ProgressLine::finish() {
  if (mode_ == ProgressMode::tty) log_ << "\n";
}

}  // namespace sluice
