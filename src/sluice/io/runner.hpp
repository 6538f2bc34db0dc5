// A run driven step by step. `sluice run` (run_case) drives one to its end; the Python module drives
// one a step, a time or a callback at a time. Either way the steps, the outputs after each, the
// instability guard and the checkpoints are the same code.
#pragma once

#include <limits>
#include <memory>
#include <ostream>

#include "sluice/case/case.hpp"
#include "sluice/io/run.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

class Runner {
 public:
  // Starts a run: of `c` at t = 0, or of the checkpoint options.restart (`c` is then ignored). The
  // memory, the starting state and the outputs planned are checked, the output directory is locked
  // and prepared, and a fresh run's first frame is written. With no output directory
  // (options.output_dir empty) nothing is written and no checkpoint is taken; the steps are still
  // those of a run that writes (they land on the same frame, checkpoint and end times), so that the
  // particles after each step are bit for bit that run's. Throws as run_case does.
  Runner(const Case& c, RunOptions options, std::ostream& log);
  ~Runner();
  Runner(const Runner&) = delete;
  Runner& operator=(const Runner&) = delete;

  [[nodiscard]] const Simulation& simulation() const;
  // The state between steps, for changes a caller makes to it (the Python module's coupling hooks).
  [[nodiscard]] Simulation& simulation();
  [[nodiscard]] double end_time() const;       // the time the run stops at (stop_time)
  [[nodiscard]] bool at_end() const;           // the end time reached
  [[nodiscard]] bool stopped() const;          // stopped on request, finished, or stopped by an error
  [[nodiscard]] bool writes_outputs() const;   // an output directory was given

  // One step, ending on the next frame, checkpoint or end time if it would pass it, and on `limit`,
  // then the outputs due after it. Returns false without stepping at the end, or when a stop is
  // requested (options.stop_requested; the run is then stopped: finish() writes its last state). An
  // error stops the run with the last good state saved (InstabilityError, RunFailure).
  bool step(double limit = std::numeric_limits<double>::infinity());
  // Steps until the time reaches t, the last step cut to end exactly on it, or the end time; false
  // if a stop was requested first.
  bool advance_to(double t);
  // The end of the run, also after a stop: the last frame (unless the last step wrote it), a
  // checkpoint and the summary. Once; afterwards the runner only answers questions.
  RunResult finish();
  // advance_to(end_time()), then finish().
  RunResult run();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sluice
