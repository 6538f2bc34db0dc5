// The progress of a run on its log: one line rewritten in a terminal ("tty"), a line every 5 % of the
// run or 30 s of wall time otherwise ("lines"), or nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>

#include "sluice/simulation.hpp"

namespace sluice {

enum class ProgressMode { tty, lines, none };

// "m:ss" or "h:mm:ss"; "--:--" for a duration not known.
[[nodiscard]] std::string format_duration(double seconds);

class ProgressLine {
 public:
  ProgressLine(ProgressMode mode, std::ostream& log, double t_start, double t_end, std::size_t particles);

  // After a step: `steps` steps in `wall` seconds of this run. `force` prints whatever the interval.
  void update(const Simulation& sim, std::int64_t steps, double wall, bool force = false);
  void finish();  // ends a rewritten line

 private:
  ProgressMode mode_;
  std::ostream& log_;
  double t_start_, t_end_;
  std::size_t particles_;
  double last_wall_ = -1e9;
  double next_line_t_ = -1e300;
};

}  // namespace sluice
