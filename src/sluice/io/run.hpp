// A run: a Simulation driven to its end time with frames, diagnostics, probes, checkpoints, a
// progress line and a summary. The CLI is a thin layer over this.
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <optional>
#include <ostream>

#include "sluice/case/case.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

struct RunOptions {
  std::filesystem::path output_dir;
  int threads = 1;
  std::optional<std::filesystem::path> restart;  // continue from this checkpoint
  // Progress reporting: "tty" rewrites one line, "lines" prints periodic lines, "none" is quiet.
  enum class Progress { tty, lines, none } progress = Progress::lines;
  const std::atomic<bool>* stop_requested = nullptr;  // set by Ctrl-C: stop after the current step
};

struct RunResult {
  Diagnostics final;
  std::size_t particles = 0;
  std::int64_t steps_this_run = 0;
  int force_evaluations_per_step = 1;
  double wall_seconds = 0.0;          // this run (not counting time before a restart)
  double particle_steps_per_second = 0.0;
  int frames_written = 0;
  bool interrupted = false;
  double rest_density = 0.0;
  double sound_speed = 0.0;
  std::filesystem::path output_dir;
  std::string case_name;
};

// Files a run writes into its output directory.
namespace output_files {
inline constexpr const char* frames_dir = "frames";
inline constexpr const char* diagnostics = "diagnostics.csv";
inline constexpr const char* checkpoint = "checkpoint.bin";
inline constexpr const char* probes_dir = "probes";
inline constexpr const char* summary = "summary.txt";
}  // namespace output_files

// Runs `c` (ignored when options.restart is set: the checkpoint carries its case). Throws IoError on
// output failures and FormatError on a bad checkpoint; `log` receives progress and the summary.
RunResult run_case(const Case& c, const RunOptions& options, std::ostream& log);

std::string format_summary(const RunResult& r);

}  // namespace sluice
