// `sluice validate --bodies`: floating bodies against hydrostatics and the NTNU section's decay tests.
//
//   floating_box      the built-in box of density 500 kg/m^3, 0.2 m tall: its draft (the water level at
//                     its gauge less its bottom, both averaged from 2 s on) against half its height
//   ntnu_heave_decay  the NTNU section in the still flume (the flap at rest) at dx = 0.01 m, started
//                     with a heave velocity of 0.1 m/s: its heave period against the measured 1.17 s
//   ntnu_roll_decay   the same started with a roll rate of 20 deg/s: its roll period against 1.26 s
//   ntnu_forces_2062  the section held at its draft in the waves of run 2062: the first harmonics of
//                     the water's horizontal and vertical force against the transducer's
//   ntnu_motions_3061_1, ntnu_motions_3102_1
//                     the section free on its rig in the waves of those runs: the first harmonics of
//                     its sway, heave and roll against the record's (amplitude and phase), the mean
//                     sway drift stated
//
// The flap follows the run's own record of it (`WM_Position`), so that the simulation and the record
// share one clock. The record's motion tracker keeps a clock of its own: in run 3061_1 its heave leads
// the record's heave accelerometers by 106 degrees where a harmonic motion's acceleration is opposite
// it (180 degrees), in run 3102_1 by 10 degrees. The motions' phases are compared on the accelerometers'
// clock: the tracker's series moved by the delay that makes its heave opposite the accelerometers'
// mean heave acceleration (tracker_delay), the same delay for its sway and roll. A body on its rig
// also moves slowly under the waves (the record's sway swings by about a centimetre over the window
// of run 3061_1, at no wave frequency): each motion's first harmonic is fitted together with a
// straight line in time in place of its mean, so that the slow motion does not leak into it.
//
// A decay's period is the mean interval between the upward crossings of the motion's mean (its mean
// over the run's second half; a crossing counted once the motion has been 5 % of its largest
// excursion below it); its damping ratio, stated, is log(a_k / a_k+1) / (2 pi) over its successive
// maxima, the mean over the first three.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sluice/analysis/reference_data.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/analysis/validation.hpp"
#include "sluice/analysis/wave_gauges.hpp"

namespace fs = std::filesystem;

namespace sluice::analysis {

namespace {

constexpr double none = std::numeric_limits<double>::infinity();  // a check with nothing measured fails

struct DecayTest {
  const char* name;
  const char* start;      // the --set that starts it
  const char* motion;     // the bodies/section.csv column
  const char* quantity;   // in words
  double measured_period;
};
constexpr DecayTest decays[] = {
    {"ntnu_heave_decay", "wall[2].floating.velocity=[0.0, 0.1]", "y", "heave (centre of gravity's y, m)", 1.17},
    {"ntnu_roll_decay", "wall[2].floating.angular_velocity=[20.0]", "angle", "roll (deg)", 1.26}};

const DecayTest* decay_of(const std::string& name) {
  for (const auto& d : decays)
    if (name == d.name) return &d;
  return nullptr;
}

// The section in the waves of an NTNU run. The flap follows the run's record from the file's
// time_offset on (the file's time is t - time_offset: the flap starts at t = 4 s); the record is
// compared over whole periods from window_start (the file's time) where its motions or forces are
// steady, before the waves the model reflects return from the flap.
struct WaveRun {
  const char* name;
  const char* record;
  const char* flap_column;
  double time_offset;
  double period;
  double window_start;
  int periods;
  double end;  // of the run, after the window's end
  bool held;   // run 2062: the model held at its draft (every degree of freedom locked)
};
constexpr WaveRun wave_runs[] = {
    {"ntnu_forces_2062", "ntnu_flume2025_2062.csv", "WM_Position [m]", -13.22, 1.158, 29.6, 7, 25.0, true},
    {"ntnu_motions_3061_1", "ntnu_flume2025_3061_1.csv", "WM_Position", -12.98, 1.158, 29.0, 8, 26.0, false},
    {"ntnu_motions_3102_1", "ntnu_flume2025_3102_1.csv", "WM_Position", -12.04, 0.897, 29.0, 10, 26.0, false}};

const WaveRun* wave_run_of(const std::string& name) {
  for (const auto& w : wave_runs)
    if (name == w.name) return &w;
  return nullptr;
}

// When the flap starts, on the simulation's clock: each record begins 4 s before it.
constexpr double flap_start = 4.0;

// The model's length across the 0.6 m flume: the record's forces are on it, the simulation's per metre.
constexpr double ntnu_model_length = 0.586;

// A column of a bodies/<name>.csv file against its time.
Series csv_column(const fs::path& file, const std::string& column) {
  return read_csv_table(file).series("time", column);
}

double mean_from(const Series& s, double t0) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.t.size(); ++i)
    if (s.t[i] >= t0) sum += s.y[i], ++n;
  return n ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

struct DecayMeasure {
  double period = std::numeric_limits<double>::quiet_NaN();
  double damping_ratio = std::numeric_limits<double>::quiet_NaN();
  int cycles = 0;
  double mean = 0.0;
};

DecayMeasure measure_decay(const Series& s) {
  DecayMeasure m;
  if (s.t.size() < 3) return m;
  m.mean = mean_from(s, 0.5 * s.t.back());
  // An upward crossing counts once the motion has been below the mean by 5 % of its largest
  // excursion: the noise of a decayed motion about its mean crosses it many times.
  double largest = 0.0;
  for (double v : s.y) largest = std::max(largest, std::abs(v - m.mean));
  const double band = 0.05 * largest;
  std::vector<double> ups;
  bool below = false;
  for (std::size_t i = 1; i < s.t.size(); ++i) {
    const double a = s.y[i - 1] - m.mean, b = s.y[i] - m.mean;
    below = below || a < -band;
    if (below && a < 0.0 && b >= 0.0) {
      ups.push_back(s.t[i - 1] + (s.t[i] - s.t[i - 1]) * (-a) / (b - a));
      below = false;
    }
  }
  if (ups.size() >= 2) {
    m.cycles = static_cast<int>(ups.size()) - 1;
    m.period = (ups.back() - ups.front()) / m.cycles;
  }
  // The largest excursion above the mean between successive upward crossings, one per cycle.
  std::vector<double> peaks;
  for (std::size_t k = 0; k + 1 < ups.size(); ++k) {
    double top = 0.0;
    for (std::size_t i = 0; i < s.t.size(); ++i)
      if (s.t[i] > ups[k] && s.t[i] < ups[k + 1]) top = std::max(top, s.y[i] - m.mean);
    peaks.push_back(top);
  }
  double sum = 0.0;
  int n = 0;
  for (std::size_t k = 0; k + 1 < peaks.size() && n < 3; ++k, ++n)
    sum += std::log(peaks[k] / peaks[k + 1]) / (2.0 * std::numbers::pi);
  if (n > 0) m.damping_ratio = sum / n;
  return m;
}

}  // namespace

double tracker_delay(const Series& heave, const Series& heave_acceleration, double omega, double t0, double t1) {
  // eta = A cos(omega t - phi): a harmonic motion's acceleration has phi + pi; a tracker delayed by tau
  // shows phi + omega tau.
  const double tracked = fit_harmonics(heave, omega, 1, t0, t1).phase[0];
  const double accelerated = fit_harmonics(heave_acceleration, omega, 1, t0, t1).phase[0];
  return std::remainder(tracked - accelerated + std::numbers::pi, 2.0 * std::numbers::pi) / omega;
}

const std::vector<std::string>& body_validation_cases() {
  static const std::vector<std::string> names = {"floating_box",     "floating_box_3d",     "ntnu_heave_decay",
                                                 "ntnu_roll_decay",  "ntnu_forces_2062",    "ntnu_motions_3061_1",
                                                 "ntnu_motions_3102_1"};
  return names;
}

const std::vector<std::string>& quick_body_validation_cases() {
  static const std::vector<std::string> names = {"floating_box", "ntnu_heave_decay", "ntnu_roll_decay"};
  return names;
}

bool is_body_case(const std::string& case_name) {
  const auto& b = body_validation_cases();
  return std::find(b.begin(), b.end(), case_name) != b.end();
}

ValidationCaseSource body_case_source(const std::string& case_name) {
  if (const DecayTest* d = decay_of(case_name))
    return {"ntnu_section",
            {"wall[1].rotation.time_offset=1000", d->start, "domain.dx=0.01", "time.end=6", "output.interval=0.5"}};
  if (const WaveRun* w = wave_run_of(case_name)) {
    std::vector<std::string> sets = {fmt::format("wall[1].rotation.file={}", w->record),
                                     fmt::format("wall[1].rotation.column={}", w->flap_column),
                                     fmt::format("wall[1].rotation.time_offset={:.17g}", w->time_offset),
                                     fmt::format("time.end={:.17g}", w->end), "domain.dx=0.01"};
    if (w->held) sets.push_back(R"(wall[2].floating.lock=["x", "y", "rz"])");
    return {"ntnu_section", sets};
  }
  // The 3D box's draft six spacings: within 0.2 % of Archimedes', where 0.02 m is 1.4 % short.
  if (case_name == "floating_box_3d") return {case_name, {"domain.dx=0.016666666666666666"}};
  return {case_name, {}};
}

std::vector<std::string> quick_body_sets(const std::string& case_name) {
  // dx = 0.02 m: the box 10 particles tall, the section's draft 10; the decays over three periods.
  if (case_name == "floating_box") return {"domain.dx=0.02"};
  // The 3D box at its case's dx = 0.02 m: at 0.04 m it is 7.5 particles wide, placed off its centre,
  // and tips over.
  if (case_name == "floating_box_3d") return {"domain.dx=0.02"};
  if (decay_of(case_name)) return {"domain.dx=0.02", "time.end=4.5"};
  if (wave_run_of(case_name)) return {"domain.dx=0.02"};
  throw AnalysisError(fmt::format("no floating-body validation case '{}'", case_name));
}

void check_body_case(const std::string& case_name, const Case& c) {
  const auto floating = [&](const std::string& name) -> const Region* {
    for (const Region& w : c.walls)
      if (w.floats && w.name == name) return &w;
    return nullptr;
  };
  const bool box_case = case_name == "floating_box" || case_name == "floating_box_3d";
  const int dimension = case_name == "floating_box_3d" ? 3 : 2;
  if (c.dimension != dimension)
    throw AnalysisError(fmt::format("case '{}': the validation case '{}' is {}D", c.name, case_name, dimension));
  if (box_case) {
    const Region* box = floating("box");
    if (!box || box->shape != Shape::box || box->floating.density <= 0.0 || box->floating.mass > 0.0)
      throw AnalysisError(fmt::format("case '{}': the buoyancy check needs its floating box 'box' given by its density",
                                      c.name));
    if (std::none_of(c.probes.begin(), c.probes.end(), [](const Probe& p) { return p.name == "level_near"; }))
      throw AnalysisError(fmt::format("case '{}': no gauge 'level_near', which the draft is measured from", c.name));
    return;
  }
  const WaveRun* wave = wave_run_of(case_name);
  if (!decay_of(case_name) && !wave)
    throw AnalysisError(fmt::format("no floating-body validation case '{}'", case_name));
  const Region* section = floating("section");
  if (!section || std::abs(section->floating.mass - 79.9) > 1e-9)
    throw AnalysisError(fmt::format("case '{}': the NTNU tests are of the NTNU section (wall 'section', 79.9 kg per "
                                    "metre)",
                                    c.name));
  if (!wave) return;
  if (c.walls.size() < 2 || c.walls[1].rotation.law != MotionLawType::file ||
      fs::path(c.walls[1].rotation.file).filename() != wave->record ||
      std::abs(c.walls[1].rotation.time_offset - wave->time_offset) > 1e-9)
    throw AnalysisError(fmt::format("case '{}': the flap (wall[1]) must follow the record {} from its time {:g} s",
                                    c.name, wave->record, -wave->time_offset));
  const std::size_t locked = section->floating.lock.size();
  if (wave->held && locked < 3)
    throw AnalysisError(fmt::format("case '{}': run 2062 held the model: lock its x, y and rz", c.name));
  if (!wave->held && locked > 0)
    throw AnalysisError(fmt::format("case '{}': in run {} the model was free in sway, heave and roll; nothing may be "
                                    "locked",
                                    c.name, std::string(case_name).substr(13)));
  if (c.end_time < wave->end - 1e-9)
    throw AnalysisError(fmt::format("case '{}': the run must reach t = {:g} s, the end of the compared window", c.name,
                                    wave->end));
}

ValidationResult evaluate_floating_box(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                       const ValidationBounds& b) {
  check_body_case(case_name, c);
  const Region& box = *std::find_if(c.walls.begin(), c.walls.end(), [](const Region& w) { return w.name == "box"; });
  const int up = c.dimension - 1;  // gravity along -y in 2D, -z in 3D
  const double height = box.max[up] - box.min[up];
  const double expected = box.floating.density / c.rest_density * height;
  const double centre = 0.5 * (box.min[up] + box.max[up]);  // the centroid's height at the start
  ValidationResult r;
  r.case_name = case_name;
  r.title = fmt::format("A box of half the water's density floating in still water ({}D): its draft against Archimedes",
                        c.dimension);
  r.resolution = fmt::format("draft/dx = {:.3g} (dx = {:.4g} mm)", expected / c.dx, c.dx * 1e3);
  r.settings = settings_of(c);
  const Series y = csv_column(run_dir / "bodies" / "box.csv", up == 1 ? "y" : "z");
  const Series level = probe_series(run_dir, "level_near", "height");
  const double from = std::min(2.0, 0.5 * c.end_time);
  const double bottom = mean_from(y, from) - (centre - box.min[up]);
  const double draft = mean_from(level, from) - bottom;
  r.checks.push_back({case_name + ".draft", case_name + ": draft error against rho_b / rho_w x height, %",
                      std::isfinite(draft) ? 100.0 * std::abs(draft / expected - 1.0) : none, b.buoyancy_percent});
  r.notes.push_back(fmt::format("Draft {:.5f} m (the water level beside the box {:.5f} m less its bottom {:.5f} m, "
                                "means from t = {:g} s to {:g} s, while it rides the tank's standing wave) against "
                                "{:.5f} m.",
                                draft, mean_from(level, from), bottom, from, c.end_time, expected));
  Plot p;
  p.title = case_name + ": the box's bottom and the water level beside it";
  p.x_label = "t (s)";
  p.y_label = "height above the floor (m)";
  Series bottom_series = y;
  for (double& v : bottom_series.y) v -= centre - box.min[up];
  p.series.push_back(curve("box bottom (sluice)", bottom_series.t, bottom_series.y));
  p.series.push_back(curve("water level at the gauge (sluice)", level.t, level.y));
  p.series.push_back(curve("level less the expected draft", {0.0, c.end_time},
                           {mean_from(level, from) - expected, mean_from(level, from) - expected}));
  p.series.back().dashed = true;
  p.bands.push_back({from, c.end_time, "averaged"});
  r.figures.push_back({p, "The box falls in, bobs on the tank's standing wave and floats at its draft.", 0});
  return r;
}

ValidationResult evaluate_decay(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                const ValidationBounds& b) {
  check_body_case(case_name, c);
  const DecayTest& d = *decay_of(case_name);
  ValidationResult r;
  r.case_name = case_name;
  r.title = fmt::format("NTNU section, free {} decay in still water (Sundsdal et al. 2025: natural period {:.3g} s)",
                        std::string(d.quantity).substr(0, std::string(d.quantity).find(' ')), d.measured_period);
  r.resolution = fmt::format("draft/dx = {:.3g} (dx = {:.4g} mm)", 0.2 / c.dx, c.dx * 1e3);
  r.settings = settings_of(c);
  const Series s = csv_column(run_dir / "bodies" / "section.csv", d.motion);
  const DecayMeasure m = measure_decay(s);
  r.checks.push_back({case_name + ".period", fmt::format("{}: natural period error against the measured {:.3g} s, %",
                                                         case_name, d.measured_period),
                      m.cycles >= 2 ? 100.0 * std::abs(m.period / d.measured_period - 1.0) : none,
                      b.decay_period_percent});
  r.notes.push_back(fmt::format("Period {:.4g} s over {} cycles (measured {:.3g} s); damping ratio {:.3g} (the log "
                                "decrement over 2 pi, mean of the first three cycles); the motion's mean {:.5g}.",
                                m.period, m.cycles, d.measured_period, m.damping_ratio, m.mean));
  r.notes.push_back(fmt::format("Started by {} with the flap at rest; the rig's sway springs and dampers as in the "
                                "experiment.",
                                d.start));
  Plot p;
  p.title = fmt::format("{}: {}", case_name, d.quantity);
  p.x_label = "t (s)";
  p.y_label = d.quantity;
  p.series.push_back(curve("sluice", s.t, s.y));
  // A cosine of the measured period through the simulated first upward crossing, for the eye.
  if (std::isfinite(m.period)) {
    Series ref;
    double amplitude = 0.0;
    for (double v : s.y) amplitude = std::max(amplitude, std::abs(v - m.mean));
    for (std::size_t i = 0; i < s.t.size(); i += 10) {
      ref.t.push_back(s.t[i]);
      ref.y.push_back(m.mean + amplitude * std::sin(2.0 * std::numbers::pi * s.t[i] / d.measured_period) *
                                   std::exp(-2.0 * std::numbers::pi * std::max(0.0, m.damping_ratio) * s.t[i] /
                                            d.measured_period));
    }
    p.series.push_back(curve(fmt::format("the measured period {:.3g} s (a damped sine, for the eye)", d.measured_period),
                             ref.t, ref.y));
    p.series.back().dashed = true;
  }
  r.figures.push_back({p, fmt::format("The section's {} after its start, over a damped sine of the measured period.",
                                      d.quantity),
                       0});
  return r;
}

namespace {

// A record's column on the simulation's clock (t = file time + time_offset - delay), scaled.
Series record_series(const Table& record, const std::string& column, double time_offset, double scale = 1.0,
                     double delay = 0.0) {
  Series s = record.series(record.columns.front(), column);
  for (double& t : s.t) t += time_offset - delay;
  for (double& y : s.y) y *= scale;
  return s;
}

// A simulated and a measured first harmonic over the window, compared: the amplitude's error in
// percent and the phase difference in degrees (positive: the simulation lags).
struct HarmonicPair {
  Harmonics sim, measured;
  [[nodiscard]] double amplitude_error() const { return 100.0 * std::abs(sim.amplitude[0] / measured.amplitude[0] - 1.0); }
  [[nodiscard]] double phase_lag() const {
    return std::remainder(sim.phase[0] - measured.phase[0], 2.0 * std::numbers::pi) * 180.0 / std::numbers::pi;
  }
  // The phase difference in words: "12.3 degrees behind it" or "4.5 degrees ahead of it".
  [[nodiscard]] std::string lag_words() const {
    const double lag = phase_lag();
    return fmt::format("{:.1f} degrees {}", std::abs(lag), lag >= 0.0 ? "behind it" : "ahead of it");
  }
};

// `background`: fit_harmonics' degree of the slow part.
HarmonicPair harmonic_pair(const Series& sim, const Series& measured, double omega, double t0, double t1,
                           int background = 0) {
  return {fit_harmonics(sim, omega, 1, t0, t1, background), fit_harmonics(measured, omega, 1, t0, t1, background)};
}

Plot over_record(const std::string& title, const std::string& quantity, const Series& sim, const Series& measured,
                 const std::string& measured_label, double t0, double t1, double from) {
  Plot p;
  p.title = title;
  p.x_label = "t (s)";
  p.y_label = quantity;
  const auto from_on = [&](const Series& s) {
    Series o;
    for (std::size_t i = 0; i < s.t.size(); ++i)
      if (s.t[i] >= from && s.t[i] <= t1 + 1.0) o.t.push_back(s.t[i]), o.y.push_back(s.y[i]);
    return o;
  };
  const Series m = from_on(measured), si = from_on(sim);
  p.series.push_back(curve(measured_label, m.t, m.y));
  p.series.back().colour = "#444444";
  p.series.push_back(curve("sluice", si.t, si.y));
  p.bands.push_back({t0, t1, "compared"});
  return p;
}

// The incident waves at the probes before the model, for the reader: sluice's first harmonic against
// the record's over the window.
void note_probes(ValidationResult& r, const Table& record, const WaveRun& w, const fs::path& run_dir, double omega,
                 double t0, double t1) {
  for (const char* probe : {"WP_1", "WP_4"}) {
    const std::string column = fmt::format("{} [m]", probe);
    if (std::find(record.columns.begin(), record.columns.end(), column) == record.columns.end()) continue;
    const HarmonicPair h = harmonic_pair(probe_series(run_dir, probe, "height"),
                                         record_series(record, column, w.time_offset), omega, t0, t1);
    r.notes.push_back(fmt::format("The waves at {} over the same window: first harmonic {:.4f} m against the probe's "
                                  "{:.4f} m ({:+.1f} %), {}.",
                                  probe, h.sim.amplitude[0], h.measured.amplitude[0],
                                  100.0 * (h.sim.amplitude[0] / h.measured.amplitude[0] - 1.0), h.lag_words()));
  }
}

ValidationResult evaluate_wave_run(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                   const ValidationBounds& b) {
  check_body_case(case_name, c);
  const WaveRun& w = *wave_run_of(case_name);
  const Table record = reference_table(w.record);
  const double omega = 2.0 * std::numbers::pi / w.period;
  // The window on the simulation's clock.
  const double t0 = w.window_start + w.time_offset, t1 = t0 + w.periods * w.period;
  const std::string run = std::string(w.record).substr(std::string("ntnu_flume2025_").size(), 4 + !w.held * 2);
  ValidationResult r;
  r.case_name = case_name;
  r.resolution = fmt::format("draft/dx = {:.3g} (dx = {:.4g} mm)", 0.2 / c.dx, c.dx * 1e3);
  r.settings = settings_of(c);
  const fs::path bodies = run_dir / "bodies" / "section.csv";
  const std::string window = fmt::format("{:.2f} <= t <= {:.2f} s", t0, t1);
  if (w.held) {
    r.title = fmt::format("NTNU section held in the waves of run {} (T = {:g} s): the wave forces against the "
                          "transducer's (Sundsdal et al. 2025)",
                          run, w.period);
    // The transducer's y runs along the flume and its z up (its x, across the flume, sees 2 % of y's).
    struct Force {
      const char* sim;
      const char* measured;
      const char* what;
    };
    for (const Force f : {Force{"fx", "Fy [N]", "horizontal"}, Force{"fy", "Fz [N]", "vertical"}}) {
      const Series force = [&] {
        Series s = csv_column(bodies, f.sim);
        for (double& v : s.y) v *= ntnu_model_length;
        return s;
      }();
      const Series measured = record_series(record, f.measured, w.time_offset);
      const HarmonicPair h = harmonic_pair(force, measured, omega, t0, t1);
      r.checks.push_back({fmt::format("{}.{}_force", case_name, f.what),
                          fmt::format("{}: {} wave force, first-harmonic amplitude error against the transducer, %",
                                      case_name, f.what),
                          h.amplitude_error(), b.wave_force_percent});
      r.notes.push_back(fmt::format("{} force: first harmonic {:.2f} N/m x {} m = {:.2f} N against the transducer's "
                                    "{:.2f} N ({:.2f} N/m), {}; means over the window {:+.2f} N and {:+.2f} N.",
                                    f.what, h.sim.amplitude[0] / ntnu_model_length, ntnu_model_length,
                                    h.sim.amplitude[0], h.measured.amplitude[0],
                                    h.measured.amplitude[0] / ntnu_model_length, h.lag_words(), h.sim.mean,
                                    h.measured.mean));
      // Each less its mean over the window: the simulation's holds the model's buoyancy, the
      // transducer was zeroed with the model in still water.
      Series force_c = force, measured_c = measured;
      for (double& v : force_c.y) v -= h.sim.mean;
      for (double& v : measured_c.y) v -= h.measured.mean;
      r.comparisons.push_back({fmt::format("{}_force", f.what),
                               fmt::format("{} wave force (N) on the model less its mean over the window", f.what),
                               fmt::format("NTNU run {}, {}", run, f.measured), window,
                               compare(force_c, measured_c, t0, t1)});
      r.figures.push_back({over_record(fmt::format("{}: {} force on the 0.586 m model", case_name, f.what),
                                       fmt::format("{} force (N), less its mean over the window", f.what), force_c,
                                       measured_c,
                                       fmt::format("transducer ({})", f.measured), t0, t1, t0 - 6.0),
                           fmt::format("The {} wave force on the held model: sluice's per metre times {} m over the "
                                       "transducer's.",
                                       f.what, ntnu_model_length),
                           1});
    }
  } else {
    r.title = fmt::format("NTNU section free on its rig in the waves of run {} (T = {:g} s): sway, heave and roll "
                          "against the record's (Sundsdal et al. 2025)",
                          run, w.period);
    const Series heave = record.series(record.columns.front(), "Heave [m]");
    Series acceleration = record.series(record.columns.front(), "ACC_Heave_SB [m/s2]");
    const std::vector<double> ps = record.values("ACC_HEAVE_PS [m/s2]");
    for (std::size_t i = 0; i < acceleration.y.size(); ++i) acceleration.y[i] = 0.5 * (acceleration.y[i] + ps[i]);
    const double delay = tracker_delay(heave, acceleration, omega, w.window_start, w.window_start + w.periods * w.period);
    struct Motion {
      const char* sim;
      const char* measured;
      const char* what;
      const char* unit;
      double scale;  // of the record's
    };
    for (const Motion m : {Motion{"x", "Sway [m]", "sway", "m", 1.0}, Motion{"y", "Heave [m]", "heave", "m", 1.0},
                           Motion{"angle", "Roll [rad]", "roll", "deg", 180.0 / std::numbers::pi}}) {
      const Series sim = csv_column(bodies, m.sim);
      const Series measured = record_series(record, m.measured, w.time_offset, m.scale, delay);
      const HarmonicPair h = harmonic_pair(sim, measured, omega, t0, t1, 1);
      r.checks.push_back({fmt::format("{}.{}_amplitude", case_name, m.what),
                          fmt::format("{}: {} first-harmonic amplitude error against the record, %", case_name, m.what),
                          h.amplitude_error(), b.motion_amplitude_percent});
      r.checks.push_back({fmt::format("{}.{}_phase", case_name, m.what),
                          fmt::format("{}: {} first-harmonic phase difference from the record, degrees", case_name,
                                      m.what),
                          std::abs(h.phase_lag()), b.motion_phase_degrees});
      r.notes.push_back(fmt::format("{}: first harmonic {:.4g} {} against the record's {:.4g} {} ({:+.1f} %), {}.",
                                    m.what, h.sim.amplitude[0], m.unit, h.measured.amplitude[0], m.unit,
                                    100.0 * (h.sim.amplitude[0] / h.measured.amplitude[0] - 1.0), h.lag_words()));
      // Centre the plot's curves on their means over the window: the record's are from its own origin.
      Series sim_c = sim, measured_c = measured;
      for (double& v : sim_c.y) v -= h.sim.mean;
      for (double& v : measured_c.y) v -= h.measured.mean;
      r.comparisons.push_back({m.what, fmt::format("{} ({}) less its mean over the window", m.what, m.unit),
                               fmt::format("NTNU run {}, {}", run, m.measured), window,
                               compare(sim_c, measured_c, t0, t1)});
      r.figures.push_back({over_record(fmt::format("{}: {}", case_name, m.what),
                                       fmt::format("{} ({}), less its mean over the window", m.what, m.unit), sim_c,
                                       measured_c, fmt::format("record ({}, moved by the tracker's delay)", m.measured),
                                       t0, t1, t0 - 6.0),
                           fmt::format("The section's {} in the waves of run {}: sluice over the record.", m.what, run),
                           1});
      if (std::string(m.what) == "sway") {
        const double sim_drift = h.sim.mean - sim.y.front();
        const double measured_drift = h.measured.mean - mean_before(measured, flap_start - 0.5);
        r.notes.push_back(fmt::format("Mean sway drift over the window: {:+.4f} m (the record: {:+.4f} m from its level "
                                      "before the waves).",
                                      sim_drift, measured_drift));
      }
    }
    r.notes.push_back(fmt::format("The record's motion tracker runs {:+.3f} s ({:+.0f} degrees) behind its heave "
                                  "accelerometers, by the phase of its heave against theirs; its series are compared "
                                  "moved by that delay onto the accelerometers' clock, which the probes' and the "
                                  "flap's share.",
                                  delay, delay * omega * 180.0 / std::numbers::pi));
  }
  note_probes(r, record, w, run_dir, omega, t0, t1);
  r.notes.push_back(fmt::format("The flap follows the record {} ({}) from its time {:g} s; compared over {} periods, "
                                "{} (the record's {:.2f} to {:.2f} s).",
                                w.record, w.flap_column, -w.time_offset, w.periods, window, w.window_start,
                                w.window_start + w.periods * w.period));
  return r;
}

}  // namespace

ValidationResult evaluate_body_case(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                    const ValidationBounds& b) {
  if (case_name == "floating_box" || case_name == "floating_box_3d") return evaluate_floating_box(case_name, c, run_dir, b);
  if (wave_run_of(case_name)) return evaluate_wave_run(case_name, c, run_dir, b);
  return evaluate_decay(case_name, c, run_dir, b);
}

}  // namespace sluice::analysis
