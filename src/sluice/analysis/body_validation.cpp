// `sluice validate --bodies`: floating bodies against hydrostatics and the NTNU section's decay tests.
//
//   floating_box      the built-in box of density 500 kg/m^3, 0.2 m tall: its draft (the water level at
//                     its gauge less its bottom, both averaged from 2 s on) against half its height
//   ntnu_heave_decay  the NTNU section in the still flume (the flap at rest) at dx = 0.01 m, started
//                     with a heave velocity of 0.1 m/s: its heave period against the measured 1.17 s
//   ntnu_roll_decay   the same started with a roll rate of 20 deg/s: its roll period against 1.26 s
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

#include "sluice/analysis/table.hpp"
#include "sluice/analysis/validation.hpp"

namespace fs = std::filesystem;

namespace sluice::analysis {

namespace {

constexpr double none = std::numeric_limits<double>::infinity();  // a check with nothing measured fails

struct Decay {
  const char* name;
  const char* start;      // the --set that starts it
  const char* motion;     // the bodies/section.csv column
  const char* quantity;   // in words
  double measured_period;
};
constexpr Decay decays[] = {
    {"ntnu_heave_decay", "wall[2].floating.velocity=[0.0, 0.1]", "y", "heave (centre of gravity's y, m)", 1.17},
    {"ntnu_roll_decay", "wall[2].floating.angular_velocity=[20.0]", "angle", "roll (deg)", 1.26}};

const Decay* decay_of(const std::string& name) {
  for (const auto& d : decays)
    if (name == d.name) return &d;
  return nullptr;
}

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

const std::vector<std::string>& body_validation_cases() {
  static const std::vector<std::string> names = {"floating_box", "ntnu_heave_decay", "ntnu_roll_decay"};
  return names;
}

bool is_body_case(const std::string& case_name) {
  const auto& b = body_validation_cases();
  return std::find(b.begin(), b.end(), case_name) != b.end();
}

ValidationCaseSource body_case_source(const std::string& case_name) {
  if (const Decay* d = decay_of(case_name))
    return {"ntnu_section",
            {"wall[1].rotation.time_offset=1000", d->start, "domain.dx=0.01", "time.end=6", "output.interval=0.5"}};
  return {case_name, {}};
}

std::vector<std::string> quick_body_sets(const std::string& case_name) {
  // dx = 0.02 m: the box 10 particles tall, the section's draft 10; the decays over three periods.
  if (case_name == "floating_box") return {"domain.dx=0.02"};
  if (decay_of(case_name)) return {"domain.dx=0.02", "time.end=4.5"};
  throw AnalysisError(fmt::format("no floating-body validation case '{}'", case_name));
}

void check_body_case(const std::string& case_name, const Case& c) {
  const auto floating = [&](const std::string& name) -> const Region* {
    for (const Region& w : c.walls)
      if (w.floats && w.name == name) return &w;
    return nullptr;
  };
  if (c.dimension != 2) throw AnalysisError(fmt::format("case '{}': the floating-body cases are 2D", c.name));
  if (case_name == "floating_box") {
    const Region* box = floating("box");
    if (!box || box->shape != Shape::box || box->floating.density <= 0.0 || box->floating.mass > 0.0)
      throw AnalysisError(fmt::format("case '{}': the buoyancy check needs its floating box 'box' given by its density",
                                      c.name));
    if (std::none_of(c.probes.begin(), c.probes.end(), [](const Probe& p) { return p.name == "level_near"; }))
      throw AnalysisError(fmt::format("case '{}': no gauge 'level_near', which the draft is measured from", c.name));
    return;
  }
  if (!decay_of(case_name)) throw AnalysisError(fmt::format("no floating-body validation case '{}'", case_name));
  const Region* section = floating("section");
  if (!section || std::abs(section->floating.mass - 79.9) > 1e-9)
    throw AnalysisError(fmt::format("case '{}': the decay tests are of the NTNU section (wall 'section', 79.9 kg per "
                                    "metre)",
                                    c.name));
}

ValidationResult evaluate_floating_box(const Case& c, const fs::path& run_dir, const ValidationBounds& b) {
  check_body_case("floating_box", c);
  const Region& box = *std::find_if(c.walls.begin(), c.walls.end(), [](const Region& w) { return w.name == "box"; });
  const double height = box.max[1] - box.min[1];
  const double expected = box.floating.density / c.rest_density * height;
  const double centre = 0.5 * (box.min[1] + box.max[1]);  // the centroid's height at the start
  ValidationResult r;
  r.case_name = "floating_box";
  r.title = "A box of half the water's density floating in still water: its draft against Archimedes";
  r.resolution = fmt::format("draft/dx = {:.3g} (dx = {:.4g} mm)", expected / c.dx, c.dx * 1e3);
  r.settings = settings_of(c);
  const Series y = csv_column(run_dir / "bodies" / "box.csv", "y");
  const Series level = probe_series(run_dir, "level_near", "height");
  const double from = std::min(2.0, 0.5 * c.end_time);
  const double bottom = mean_from(y, from) - (centre - box.min[1]);
  const double draft = mean_from(level, from) - bottom;
  r.checks.push_back({"floating_box.draft", "floating_box: draft error against rho_b / rho_w x height, %",
                      std::isfinite(draft) ? 100.0 * std::abs(draft / expected - 1.0) : none, b.buoyancy_percent});
  r.notes.push_back(fmt::format("Draft {:.5f} m (the water level beside the box {:.5f} m less its bottom {:.5f} m, "
                                "means from t = {:g} s to {:g} s, while it rides the tank's standing wave) against "
                                "{:.5f} m.",
                                draft, mean_from(level, from), bottom, from, c.end_time, expected));
  Plot p;
  p.title = "floating_box: the box's bottom and the water level beside it";
  p.x_label = "t (s)";
  p.y_label = "height above the floor (m)";
  Series bottom_series = y;
  for (double& v : bottom_series.y) v -= centre - box.min[1];
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
  const Decay& d = *decay_of(case_name);
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

ValidationResult evaluate_body_case(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                    const ValidationBounds& b) {
  if (case_name == "floating_box") return evaluate_floating_box(c, run_dir, b);
  return evaluate_decay(case_name, c, run_dir, b);
}

}  // namespace sluice::analysis
