// Validation against experiments: the built-in validation cases (cases/martin_moyce.toml,
// cases/koshizuka_oka.toml, cases/buchner.toml) run and compared with the reference data of
// data/validation/, in the data's non-dimensional units, with a self-contained HTML report.
//
//   martin_moyce   surge front Z(T) and residual column height H(tau) against Martin & Moyce (1952)
//   koshizuka_oka  surge front Z(T) against Koshizuka & Oka (1996)
//   buchner        far-wall pressure p*(t*) at 0.2H against Buchner (2002), and the impact time
//   spheric2       (3D, --3d) pressures P1-P4 on a box obstacle and water levels H2, H4 against
//                  Kleefsman et al. (2005), SPHERIC test 2; P1's impact time (analysis/spheric2.cpp)
//
// Fronts are the furthest fluid particle's centre plus dx/2, its edge: the initial front, a particle
// centre dx/2 inside the column, is then at Z = 1 exactly, as in the experiments' scaling.
#pragma once

#include <filesystem>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/case/case.hpp"
#include "sluice/io/run.hpp"

namespace sluice::analysis {

// An accuracy requirement: value <= bound.
struct Check {
  std::string id;    // e.g. "martin_moyce.front_rms", for checks.csv
  std::string what;  // in words, for the report
  double value = 0.0;
  double bound = 0.0;
  [[nodiscard]] bool passed() const { return value <= bound; }
};

// One simulated curve against one data set.
struct Comparison {
  std::string id;         // e.g. "front_T3", for validation.csv
  std::string quantity;   // e.g. "front Z = x/a"
  std::string reference;  // e.g. "Martin & Moyce (1952) Table 2"
  std::string window;     // e.g. "T <= 3"
  Difference difference;
  // For a comparison moved in time (moved_comparison): by how much the simulation was moved, positive
  // later, in the data's time unit; NaN for the others.
  double moved_by = std::numeric_limits<double>::quiet_NaN();
};

// `base` again with the simulated curve moved in time by the constant s within +-max_shift (in steps
// of `step`) that fits the data best over [t_min, t_max] (best_lag): s is the difference in timing,
// the RMS left the difference in shape. The id gets "_moved"; the quantity says by how much, in
// `time_symbol`'s units (positive: the simulation moved later, it ran ahead of the data).
Comparison moved_comparison(const Comparison& base, const Series& simulation, const Series& reference, double t_min,
                            double t_max, double max_shift, double step, const std::string& time_symbol);

// A plot of a simulated curve against data, drawn (svg_plot) when the report is written, so that
// the --compare variants' curves can join it.
struct Figure {
  Plot plot;
  std::string caption;
  std::size_t simulated = 0;  // the simulated curve's index in plot.series
};

struct ValidationResult {
  std::string case_name;
  std::string title;
  std::string resolution;  // e.g. "a/dx = 40 (dx = 1.429 mm)"
  std::string settings;    // the physics options in one line
  std::size_t particles = 0, fluid_particles = 0;
  std::int64_t steps = 0;
  std::int64_t leaks = 0;    // fluid particles put back from inside a wall
  std::int64_t outflow = 0;  // fluid particles that went over an open tank's walls
  double wall_seconds = 0.0;
  std::vector<Comparison> comparisons;
  std::vector<Check> checks;
  std::vector<Figure> figures;
  std::vector<std::string> notes;
  [[nodiscard]] bool passed() const;
};

// Accuracy bounds: the targets for the full report, and what holds at --quick's resolution.
struct ValidationBounds {
  double mm_front_rms;        // Martin & Moyce front, RMS dZ for T <= 3
  double mm_height_rms;       // Martin & Moyce residual column height, RMS dH (0: reported only)
  double ko_front_rms;        // Koshizuka & Oka front, RMS dZ (0: reported only)
  double buchner_pressure_rms;  // Buchner probe, RMS dp* for 2 <= t* <= 7
  double buchner_plateau_rms;   // Buchner probe, RMS dp* for 3.5 <= t* <= 5.5 (0: reported only)
  double buchner_impact;      // |impact time - data's| in t*
  double spheric2_impact;     // |P1 impact time - data's| in s
  double wave_height_percent;   // wave_flume: |first-harmonic height - target| at 2, 4, 6 wavelengths, %
  double wave_period_percent;   // wave_flume: |zero-crossing period - target| at those gauges, %
  double wave_reflection;       // wave_flume: reflection coefficient Kr
  double ntnu_amplitude_percent;  // NTNU flume: |first-harmonic amplitude - measured| at each probe, %
  double ntnu_phase_degrees;      // NTNU flume: |first-harmonic phase - measured| at each probe, degrees
  double buoyancy_percent;        // floating_box: |draft - rho_b/rho_w height| / that, %
  double decay_period_percent;    // NTNU section decays: |natural period - measured| / measured, %
  double wave_force_percent;      // NTNU section held in waves: |force's first harmonic - measured| / measured, %
  double motion_amplitude_percent;  // NTNU section free in waves: |motion's first harmonic - measured| / measured, %
  double motion_phase_degrees;      // and |its phase - measured|, degrees
};
ValidationBounds full_bounds();
ValidationBounds quick_bounds();

// The column width (or, for Buchner, height) over dx at which --quick runs each case.
double quick_resolution(const std::string& case_name);

// The wave cases (analysis/wave_validation.cpp), run by `sluice validate --waves`: wave_flume against
// linear theory, and the NTNU flume's runs 1021, 1062 and 1102 against the laboratory's probes.
const std::vector<std::string>& wave_validation_cases();
bool is_wave_case(const std::string& case_name);
// The built-in case a validation case runs, and the overrides that make it that case (an NTNU run's
// record of the paddle).
struct ValidationCaseSource {
  std::string builtin;
  std::vector<std::string> sets;
};
ValidationCaseSource validation_case_source(const std::string& case_name);
// --quick's overrides of a wave case: a coarser dx and a shorter run.
std::vector<std::string> quick_wave_sets(const std::string& case_name);
// Throws AnalysisError when a wave case is no longer the one its theory or data are for.
void check_wave_case(const std::string& case_name, const Case& c);

// The floating-body cases (analysis/body_validation.cpp), run by `sluice validate --bodies`: the
// floating box's draft against Archimedes (2D and 3D), the NTNU section's heave and roll decay
// periods, its wave forces held in run 2062 and its motions free in runs 3061_1 and 3102_1; --quick
// runs the 2D box and the decays (the 3D box and the wave runs take 20-60 minutes each).
const std::vector<std::string>& body_validation_cases();
const std::vector<std::string>& quick_body_validation_cases();
bool is_body_case(const std::string& case_name);
ValidationCaseSource body_case_source(const std::string& case_name);
// --quick's overrides of a floating-body case: a coarser dx and a shorter run.
std::vector<std::string> quick_body_sets(const std::string& case_name);
// Throws AnalysisError when a floating-body case is no longer the one its data are for.
void check_body_case(const std::string& case_name, const Case& c);
// How far a record's motion tracker runs behind its accelerometers, in seconds (negative: ahead), from
// the first harmonics over [t0, t1] at angular frequency omega: the delay that makes the tracked heave,
// moved earlier by it, opposite the heave acceleration. In (-T/2, T/2].
double tracker_delay(const Series& heave, const Series& heave_acceleration, double omega, double t0, double t1);
ValidationResult evaluate_body_case(const std::string& case_name, const Case& c, const std::filesystem::path& run_dir,
                                    const ValidationBounds& b);

// Throws AnalysisError when the case is not the one its validation data are for (its column, tank or
// gravity): checked before it runs, and again by its evaluation.
void check_validation_case(const std::string& case_name, const Case& c);
// SPHERIC test 2's part of it (analysis/spheric2.cpp).
void check_spheric2_case(const Case& c);

// Evaluations of a finished run of the case (probes in run_dir/probes/).
ValidationResult evaluate_martin_moyce(const Case& c, const std::filesystem::path& run_dir, const ValidationBounds& b);
ValidationResult evaluate_koshizuka_oka(const Case& c, const std::filesystem::path& run_dir, const ValidationBounds& b);
ValidationResult evaluate_buchner(const Case& c, const std::filesystem::path& run_dir, const ValidationBounds& b);
ValidationResult evaluate_spheric2(const Case& c, const std::filesystem::path& run_dir, const ValidationBounds& b);
ValidationResult evaluate_wave_flume(const Case& c, const std::filesystem::path& run_dir, const ValidationBounds& b);
ValidationResult evaluate_ntnu_flume(const std::string& case_name, const Case& c, const std::filesystem::path& run_dir,
                                     const ValidationBounds& b);

// An experiment's (or reference solution's) series drawn over a run's own, in the live view: on the
// run's clock and in the units of the run's column `column` of `group`/`series`.csv.
struct ReferenceOverlay {
  std::string group;   // "probes"
  std::string series;  // the file's stem: the probe's name
  std::string column;  // the run's column it is drawn against
  std::string label;   // where the data come from
  // The data are departures from the water at rest (a wave gauge's elevation): drawn from the run's
  // first value of the column.
  bool from_first_value = false;
  Series data;
};
// The reference data of a validation case for its probes, or none (a case with no such data, or one
// no longer the case its data are for): Buchner's wall pressure, SPHERIC test 2's pressures and
// levels, and the wave gauges of a case whose wave maker follows an NTNU record.
std::vector<ReferenceOverlay> reference_overlays(const Case& c);
std::vector<ReferenceOverlay> spheric2_overlays(const Case& c);  // (analysis/spheric2.cpp)

// A probe's series from a finished run (run_dir/probes/<probe>.csv): time and the named column.
Series probe_series(const std::filesystem::path& run_dir, const std::string& probe, const std::string& column);

// The physics options of a case in one line, for the report.
std::string settings_of(const Case& c);

// The impact time: the first time a pressure signal reaches `level` (p*), interpolated.
inline constexpr double impact_pressure_level = 0.25;

// The cases run again with other settings, reported beside the main run (sluice validate --compare):
// e.g. another wall treatment beside the default one.
struct ValidationVariant {
  std::string label;              // names its column and its directory, variants/<label>/
  std::vector<std::string> sets;  // key=value overrides, applied after the main run's
  bool two_d_only = false;        // runs the 2D dam breaks only (the dynamic walls' column), not the wave cases
};

// The column validate adds unless told not to: dynamic walls at h = 1.3 dx without shifting or the
// wall function (the default case's formulation), beside the validation cases' own settings, on the
// 2D cases.
ValidationVariant dynamic_walls_variant();

// A --compare argument, "LABEL: KEY=VALUE; KEY=VALUE ...", as a variant. Throws AnalysisError naming
// what is wrong: no label or no override, or a label that is not a plain name (letters, digits, and
// . _ + -).
ValidationVariant parse_variant(const std::string& text);
// Throws AnalysisError if two variants share a label (their runs would share a directory).
void check_variant_labels(const std::vector<ValidationVariant>& variants);

struct ValidationOptions {
  bool quick = false;
  std::filesystem::path output_dir;        // holds report.html, validation.csv and runs/<case>/
  int threads = 1;
  RunOptions::Progress progress = RunOptions::Progress::none;
  std::vector<std::string> cases;          // empty: the 2D cases, and with `three_d` the 3D one
  bool three_d = false;                    // also the 3D case (spheric2)
  bool waves = false;                      // the wave cases instead of the dam breaks (with `cases` empty)
  bool bodies = false;                     // the floating-body cases instead (with `cases` empty)
  std::vector<std::string> sets;           // key=value overrides applied to every case (after --quick's dx)
  std::vector<ValidationVariant> variants;  // every case run again with each, after `sets` (distinct labels)
  std::string command_line;                // recorded in the report
};

struct ValidationReport {
  bool quick = false;
  std::vector<ValidationResult> results;  // the main run's, which the checks (and the exit status) are of
  struct Variant {
    ValidationVariant variant;
    std::vector<ValidationResult> results;  // in the order of `results`
  };
  std::vector<Variant> variants;
  [[nodiscard]] bool passed() const;
};

// The case names validate can run, in report order: the 2D cases, the 3D one, then the wave cases.
const std::vector<std::string>& validation_case_names();
// Those that run by default (2D); --3d adds spheric2.
const std::vector<std::string>& default_validation_cases();

// Runs the cases, evaluates them and writes report.html, validation.csv (one row per comparison:
// case,comparison,points,rms,max,mean,quantity,reference,window) and checks.csv (one row per
// requirement: check,value,bound,passed) into options.output_dir.
ValidationReport run_validation(const ValidationOptions& options, std::ostream& log);

std::string validation_csv(const ValidationReport& report);
std::string checks_csv(const ValidationReport& report);
std::string validation_html(const ValidationReport& report, const std::string& command_line);
std::string validation_table(const ValidationReport& report);  // for the terminal

}  // namespace sluice::analysis
