// A run: a Simulation driven to its end time with frames, diagnostics, probes, checkpoints, a
// progress line and a summary. The CLI is a thin layer over this; the pieces are the outputs
// (run_outputs.hpp), the schedule of frames and checkpoints (schedule.hpp), the progress line
// (progress.hpp), the checks before a run (run_checks.hpp) and the run itself (runner.hpp).
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/communicator.hpp"
#include "sluice/io/progress.hpp"
#include "sluice/io/run_outputs.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

struct RunOptions {
  std::filesystem::path output_dir;
  int threads = 1;
  // Step with fewer of the threads while fewer are faster (a busy machine; io/thread_governor.hpp).
  // Off, every step uses `threads`: for measuring the speed of a thread count.
  bool adapt_threads = true;
  std::optional<std::filesystem::path> restart;  // continue from this checkpoint
  // With a restart: "key=value" changes to the stored case. Only time.end may change (to run on past
  // the end of the run that wrote the checkpoint); anything else would break the exact continuation.
  std::vector<std::string> restart_overrides;
  // Progress reporting: "tty" rewrites one line, "lines" prints periodic lines, "none" is quiet.
  using Progress = ProgressMode;
  Progress progress = Progress::lines;
  const std::atomic<bool>* stop_requested = nullptr;  // set by Ctrl-C: stop after the current step
  // Set by a live view's page (sluice run --view): wait between steps while `pause_requested`; write a
  // checkpoint after the current step when `checkpoint_requested` (which the run clears).
  const std::atomic<bool>* pause_requested = nullptr;
  std::atomic<bool>* checkpoint_requested = nullptr;
  // The processes of an MPI run (null for one process): the particles are spread over them, the root
  // writes every output file and the progress, and an output error on the root stops every process.
  const Communicator* comm = nullptr;
  // What the run is, as the output directory's lock names its holder to a second run refused there
  // (io/directory_lock.hpp); the case's name is added.
  std::string command = "sluice run";
};

// The run went unstable (non-finite values, particles far outside the tank, absurd densities). The
// message names the time, the step and the first offending particles, and where the last good state
// was saved.
struct InstabilityError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A process failed in the middle of a run (out of memory, a broken invariant): every process stops
// with this error, which names the process, the time and the step, and where the last good state
// was saved (the state before the step the error cut short).
struct RunFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An error every process of a run meets alike, where all stop together with it: bad input (every
// process reads the same case), a damaged file read by all, an output error (the root's, sent to all),
// an unstable run and a run failure (agreed over all processes: Communicator::fail).
[[nodiscard]] bool fails_alike(const std::exception& e);

// An error's message for the user, with advice for running out of memory.
[[nodiscard]] std::string error_text(const std::exception& e);

struct RunResult {
  Diagnostics final;
  std::size_t particles = 0;
  std::int64_t steps_this_run = 0;
  int force_evaluations_per_step = 1;
  double wall_seconds = 0.0;          // this run (not counting time before a restart)
  double loop_seconds = 0.0;          // the stepping loop of this run
  double particle_steps_per_second = 0.0;
  int frames_written = 0;
  // The steps of this run at each thread count, most threads first (one entry unless the run came
  // down to fewer threads on a busy machine).
  std::vector<std::pair<int, std::int64_t>> thread_steps;
  bool interrupted = false;
  double rest_density = 0.0;
  double sound_speed = 0.0;
  bool single_precision_pairs = false;  // domain.pair_precision = "single"
  std::filesystem::path output_dir;
  std::string case_name;
  int processes = 1;
  // With several processes: bytes sent between them in this run (all processes), and the longest time
  // one spent in the particle exchanges (waiting for the others included).
  double bytes_exchanged = 0.0;
  double exchange_seconds = 0.0;
  double ghost_share = 0.0;  // ghosts per owned particle, all processes, averaged over the evaluations
  std::vector<std::string> notes;  // the set-up's (Solver::setup_notes), for a run that started the case
};

// Runs `c` (ignored when options.restart is set: the checkpoint carries its case). Throws IoError on
// output failures, FormatError on a bad checkpoint and CaseError on a restart that cannot continue
// (a forbidden override, or a checkpoint already at the end time); `log` receives progress.
//
// A restart continues bit for bit as the run that never stopped would have (same thread count),
// provided the checkpoint was taken at a time that run also stops at: a periodic checkpoint, a
// Ctrl-C, or an end time that is a frame time. Frames after the checkpoint are (re)written; earlier
// frames, diagnostics rows and probe samples on disk are kept.
RunResult run_case(const Case& c, const RunOptions& options, std::ostream& log);

std::string format_summary(const RunResult& r);

}  // namespace sluice
