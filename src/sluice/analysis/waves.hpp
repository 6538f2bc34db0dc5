// Waves in a run's frames: the crest (highest fluid point), the front of the wave running over the
// bed, the horizontal centre of mass (whose oscillation is the sloshing), and what follows from them:
// crest speeds over the tank's transits, the time the wave takes to reach the far wall, and the
// sloshing period, with the shallow-water references they compare against.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"
#include "sluice/case/case.hpp"
#include "sluice/io/frames.hpp"

namespace sluice::analysis {

// The free surface over columns of width `column_width` from x = 0: the top of the highest fluid
// particle in each column (its centre plus dx/2), or 0 for a column without water (the floor).
struct SurfaceProfile {
  double column_width = 0.0;
  std::vector<double> top;
  [[nodiscard]] double at(double x) const;  // the column holding x (clamped to the profile)
};
SurfaceProfile surface_profile(const Frame& f, double width, double column_width);

struct Crest {
  double x = 0.0;       // x of the highest fluid particle
  double height = 0.0;  // its top: y + dx/2
};
Crest crest(const Frame& f);

double centre_of_mass_x(const Frame& f);

// The front of a wave running to +x: the largest x of a fluid particle whose top stands more than
// `threshold` above the initial surface at its x. Over a dry bed (initial surface 0) and a small
// threshold this is the furthest particle; over a wet bed it is the bore, not the still water ahead
// of it. nullopt if no particle stands that high.
std::optional<double> wave_front(const Frame& f, const SurfaceProfile& initial, double threshold);

// One crossing of the crest over the middle half of the tank.
struct Transit {
  int direction = 0;            // +1 to the right, -1 to the left
  double t_start = 0.0, t_end = 0.0;
  double speed = 0.0;           // |slope| of a straight line through the crest positions
};
// Transits of a crest path x(t) in a tank of width `width`: runs of consecutive samples with the crest
// in [width/4, 3 width/4] that move it at least width/4 in one direction. A jump of more than width/8
// between two samples (the highest point passing from one hump to another) ends a run; runs of fewer
// than 3 samples are ignored.
std::vector<Transit> find_transits(const Series& crest_x, double width);

// Stoker's (1957) wet-bed dam-break bore speed S / sqrt(g h_upstream) for a depth ratio
// h_downstream / h_upstream, interpolated in data/validation/stoker_wetbed_table.csv; the ratio 0 gives
// Ritter's dry-bed front speed 2. Throws outside [0, 0.9].
double stoker_bore_speed_ratio(double depth_ratio);

// Linear first-mode sloshing period of a tank of width L and depth h: 2 pi / sqrt(g k tanh(k h)), k = pi/L.
double first_mode_period(double width, double depth, double g);

struct WaveOptions {
  // Height above the initial surface that marks the wave front; 0: 10% of the initial depth difference
  // between the two walls for a dam break (a step in the initial surface), else 10% of the mean depth.
  double front_threshold = 0.0;
  int transits = 3;  // the mean crest speed is over this many first transits
};

struct WaveAnalysis {
  // Time series, one sample per frame.
  std::vector<double> time, crest_x, crest_height, front, centre_of_mass_x, far_wall_height;
  double width = 0.0, dx = 0.0;
  double mean_depth = 0.0;          // h0: fluid area / tank width
  double upstream_depth = 0.0;      // initial surface at the left wall
  double downstream_depth = 0.0;    // initial surface at the right wall
  bool dam_break = false;           // the initial surface drops in one step (between two columns)
  double front_threshold = 0.0;
  double shallow_water_speed = 0.0; // sqrt(g h0)
  std::optional<double> stoker_speed;   // for upstream > downstream
  std::optional<double> far_wall_arrival;  // first time the surface at the far wall rises by the threshold
  std::optional<LineFit> front_fit;     // the front over the middle half of the tank, first transit
  std::vector<Transit> transits;
  std::optional<double> mean_crest_speed;  // over the first WaveOptions::transits transits
  int transits_averaged = 0;
  std::optional<PeriodEstimate> period_zero_crossings;  // of the centre of mass
  std::optional<double> period_autocorrelation;
  double linear_period = 0.0;       // first mode at the mean depth
  double shallow_water_period = 0.0;  // 2 L / sqrt(g h0)
  std::vector<std::string> notes;   // what could not be measured, and why
  SurfaceProfile initial_surface;
  int transits_wanted = 3;
};

// `frames` in time order; the first is the initial state. `width` is the tank's inner width, `g` > 0.
WaveAnalysis analyze_waves(const std::vector<Frame>& frames, double width, double g, const WaveOptions& options);

// The same, one frame at a time: start from the initial frame, add every frame (the initial one too) in
// time order, then finish (the transits, speeds and periods).
WaveAnalysis start_wave_analysis(const Frame& first, double width, double g, const WaveOptions& options);
void add_frame(WaveAnalysis& a, const Frame& f);
void finish_wave_analysis(WaveAnalysis& a);

// The frames/frame_NNNNNN.npz of a run's output directory, in order. Throws AnalysisError if none.
std::vector<std::filesystem::path> list_npz_frames(const std::filesystem::path& output_dir);

// Reads a run's NumPy frames and analyses them with the case's tank width and gravity (straight down).
WaveAnalysis analyze_run(const std::filesystem::path& output_dir, const Case& c, const WaveOptions& options);

}  // namespace sluice::analysis
