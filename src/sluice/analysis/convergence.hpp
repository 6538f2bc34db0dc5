// A convergence study: one case run at several particle spacings (h/dx fixed), each compared with the
// finest run. Two error measures of the wave's first transit of the tank:
//   front: RMS difference of the wave-front position x_front(t) from the finest run's, over the frames
//          from t = 0 until the finest run's wave reaches the far wall;
//   arrival: |time the wave reaches the far wall - the finest run's|, from a gauge at the far wall
//          sampled every step (the surface there rising by the front threshold).
// The observed order between two spacings is p = log(e1/e2) / log(dx1/dx2).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"
#include "sluice/case/case.hpp"
#include "sluice/io/run.hpp"

namespace sluice::analysis {

struct ConvergenceOptions {
  std::vector<double> dx;        // at least 3, any order (run coarsest first)
  double end_time = 0.0;         // 0: 1.2 L / sqrt(g h0), at most the case's end
  double frame_interval = 0.0;   // 0: L / sqrt(g h0) / 50
  double front_threshold = 0.0;  // 0: as sluice analyze (10% of the initial step between the walls)
  int threads = 1;
  std::filesystem::path output_dir;
  RunOptions::Progress progress = RunOptions::Progress::none;
  std::string command_line;      // recorded in the report
};

struct ConvergenceLevel {
  double dx = 0.0;
  std::size_t particles = 0, fluid_particles = 0;
  std::int64_t steps = 0;
  double wall_seconds = 0.0;
  Series front;                    // wave-front position at the frame times where there is a front
  std::optional<double> arrival;   // the wave reaches the far wall
  // Against the finest level (NaN for the finest itself or when not measurable):
  double front_error = std::nan("");
  double arrival_error = std::nan("");
  // Observed orders between this level and the next finer one that has an error (NaN if none).
  double front_order = std::nan("");
  double arrival_order = std::nan("");
};

struct ConvergenceStudy {
  std::string case_name;
  double width = 0.0, mean_depth = 0.0, front_threshold = 0.0, end_time = 0.0, frame_interval = 0.0;
  double h_over_dx = 0.0;
  std::vector<ConvergenceLevel> levels;  // coarsest first; the last is the reference
  std::vector<std::string> notes;
};

// Fills the errors and orders of study.levels (each with its front and arrival set).
void compute_convergence_errors(ConvergenceStudy& study);

// Runs the case at every spacing (into output_dir/dx_<dx>/), measures the errors and writes
// convergence.csv, convergence.svg (log-log errors), fronts.svg and report.html into output_dir.
ConvergenceStudy run_convergence(const Case& c, const ConvergenceOptions& options, std::ostream& log);

std::string convergence_table(const ConvergenceStudy& study);
std::string convergence_csv(const ConvergenceStudy& study);

}  // namespace sluice::analysis
