// `sluice analyze` on a wave flume: a run whose case has a wave maker (law = "wave"), a paddle driven by
// a laboratory record that also holds the gauges' measurements, or whose user names the wave
// (--period): the regular waves at each gauge against linear theory or the measurement, the decay of
// the first harmonic along the flume and the reflection, as a table, CSVs, SVG plots and an HTML page.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/wave_gauges.hpp"
#include "sluice/case/case.hpp"

namespace sluice::analysis {

struct FlumeOptions {
  // The wave, when the case's wave maker does not say it (a paddle driven by a recorded motion):
  // period (s), height (m, 0 = none to compare with) and depth (m, 0 = the still level at the gauges).
  double period = 0.0, height = 0.0, depth = 0.0;
  std::optional<double> maker_x;   // where distances are measured from (default: the wave maker's face)
  std::optional<Window> window;    // the same window at every gauge (default: each gauge's steady window)
};

// The wave the flume is asked for: from the case's wave maker or the options.
struct FlumeWave {
  std::string maker;  // the wall's key, e.g. "wall[0].translation"; empty when from the options
  double height = 0.0, period = 0.0, depth = 0.0;
  double wavelength = 0.0, k = 0.0, omega = 0.0, group_velocity = 0.0;
  // The amplitude of Stokes' second-order bound harmonic of the target wave,
  // (k a^2 / 4) cosh(kh) (2 + cosh 2kh) / sinh^3(kh), a = H/2: what the second harmonic should be
  // everywhere when no free second harmonic is made (second-order generation); 0 without a target.
  double bound_second_harmonic = 0.0;
  double start = 0.0, ramp_time = 0.0;  // when the maker starts, and how long it ramps up
  double maker_x = 0.0;                 // the paddle's face at rest (a flap: its hinge)
  int order = 1;
  // A paddle driven by a record (law = "file"): the file, and the run's time minus the file's. Its
  // period, start and ramp are read from the record when the options do not give them.
  std::string record;
  double record_time_offset = 0.0;
};

struct GaugeWaves {
  std::string name;
  double x = 0.0, distance = 0.0;  // distance from the maker (m)
  Series eta;                      // the surface elevation (the level minus the still level)
  std::optional<Window> window;    // nullopt: no steady waves reach it in the run
  std::optional<ZeroCrossingWaves> zero_crossing;
  std::optional<Harmonics> harmonics;  // first and second
  double theory_phase = 0.0;       // of the first harmonic, linear theory from the maker's motion
  // The still water's depth over the gauge's foot, and linear theory's shoaling coefficient
  // Ks = sqrt(cg(h_maker) / cg(h_gauge)) for it: a gauge over another depth (a beach) is compared with
  // the target's height times Ks, has no theory phase (that depends on the bed between), and stays
  // out of the decay and the reflection.
  double depth = 0.0, shoaling = 1.0;
  bool other_depth = false;
  std::string note;                // why a measurement is missing
  // The laboratory's series for this gauge (the record's column named as the gauge, "WP_1" or
  // "WP_1 [m]"), on the run's time, its still level removed; and its harmonics over the same window.
  std::optional<Series> measured;
  std::optional<Harmonics> measured_harmonics;
};

struct FlumeAnalysis {
  FlumeWave wave;
  double still_level = 0.0;
  double end_time = 0.0;
  std::optional<double> reflector;  // the wall that reflects (distance from the maker); nullopt with a damping zone
  std::vector<GaugeWaves> gauges;
  std::optional<Decay> decay;                   // over the gauges with steady waves, outside the damping zone
  std::optional<IncidentReflected> reflection;  // over the same gauges, in one common window
  std::optional<Window> common_window;
  std::vector<std::string> reflection_gauges;
  std::vector<std::string> notes;
};

// Whether `sluice analyze` should treat the run as a wave flume: the case has a wave maker, or a paddle
// driven by a record that holds a column named as one of its gauges.
bool has_wave_maker(const Case& c);

// Throws AnalysisError when the wave cannot be known (no wave maker and no period) or the run has no
// gauges. With a recorded paddle and a damping zone (a beach), each gauge's window closes before the
// zone's start can reflect the steady waves back to it: the laboratory's beach reflects, the zone
// stands for its absorption alone.
FlumeAnalysis analyze_flume(const std::filesystem::path& run_dir, const Case& c, const FlumeOptions& options);

// Gauge g's series over the theory (or the measurement), its window shaded; the first and second
// harmonics along the flume.
Plot flume_gauge_plot(const FlumeAnalysis& a, const GaugeWaves& g);
Plot flume_harmonics_plot(const FlumeAnalysis& a);

// The table printed on the terminal.
std::string flume_table(const FlumeAnalysis& a);

// Writes into out_dir: gauges.csv (per gauge: position, window, heights, harmonics, theory), summary.csv,
// eta_<gauge>.svg (each gauge's series over the theory, its window shaded), harmonics.svg (the first and
// second harmonic along the flume) and report.html.
void write_flume_report(const FlumeAnalysis& a, const std::filesystem::path& run_dir, const std::filesystem::path& out_dir);

}  // namespace sluice::analysis
