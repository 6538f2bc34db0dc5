// `sluice validate --waves`: the wave flume against linear theory (the first harmonic's height at 2, 4
// and 6 wavelengths, the period, the reflection) and the NTNU flume's runs against the laboratory's
// probes (each probe's first-harmonic amplitude and phase), on the measurements of analysis/wave_flume.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "sluice/analysis/validation.hpp"
#include "sluice/analysis/wave_flume.hpp"

namespace fs = std::filesystem;

namespace sluice::analysis {

namespace {

constexpr double none = std::numeric_limits<double>::infinity();  // a check with nothing measured fails

struct NtnuRun {
  const char* name;
  const char* record;
  double time_offset;  // puts the flap's start at t = 1 s
};
constexpr NtnuRun ntnu_runs[] = {{"ntnu_1021", "ntnu_flume2025_1021.csv", -34.955},
                                 {"ntnu_1062", "ntnu_flume2025_1062.csv", -17.98},
                                 {"ntnu_1102", "ntnu_flume2025_1102.csv", -20.8}};

const NtnuRun* ntnu_run(const std::string& name) {
  for (const auto& r : ntnu_runs)
    if (name == r.name) return &r;
  return nullptr;
}

// The gauge nearest n wavelengths from the wave maker.
const GaugeWaves* gauge_at(const FlumeAnalysis& a, double n) {
  const GaugeWaves* best = nullptr;
  for (const auto& g : a.gauges)
    if (!best || std::abs(g.distance - n * a.wave.wavelength) < std::abs(best->distance - n * a.wave.wavelength))
      best = &g;
  return best;
}

// A series sampled at `like`'s times within [t0, t1].
Series sampled_like(const Series& like, double t0, double t1, auto f) {
  Series s;
  for (double t : like.t)
    if (t >= t0 && t <= t1) {
      s.t.push_back(t);
      s.y.push_back(f(t));
    }
  return s;
}

}  // namespace

const std::vector<std::string>& wave_validation_cases() {
  static const std::vector<std::string> names = {"wave_flume", "ntnu_1021", "ntnu_1062", "ntnu_1102"};
  return names;
}

bool is_wave_case(const std::string& case_name) {
  const auto& w = wave_validation_cases();
  return std::find(w.begin(), w.end(), case_name) != w.end();
}

ValidationCaseSource validation_case_source(const std::string& case_name) {
  if (is_body_case(case_name)) return body_case_source(case_name);
  if (const NtnuRun* run = ntnu_run(case_name))
    return {"ntnu_flume",
            {fmt::format("wall[1].rotation.file={}", run->record),
             fmt::format("wall[1].rotation.time_offset={:.17g}", run->time_offset)}};
  return {case_name, {}};
}

std::vector<std::string> quick_wave_sets(const std::string& case_name) {
  // wave_flume at H/dx = 2.5; the NTNU flume at dx = 0.04 m (H/dx = 1 for runs 1062 and 1102) until the
  // first probes' windows close.
  if (case_name == "wave_flume") return {"domain.dx=0.032"};
  if (ntnu_run(case_name)) return {"domain.dx=0.04", "time.end=16"};
  throw AnalysisError(fmt::format("no wave validation case '{}'", case_name));
}

void check_wave_case(const std::string& case_name, const Case& c) {
  if (c.dimension != 2) throw AnalysisError(fmt::format("case '{}': the wave cases are 2D flumes", c.name));
  const auto has_gauge = [&](const std::string& name) {
    return std::any_of(c.probes.begin(), c.probes.end(),
                       [&](const Probe& p) { return p.type == ProbeType::gauge && p.name == name; });
  };
  if (case_name == "wave_flume") {
    if (!has_wave_maker(c) || !c.damps())
      throw AnalysisError(fmt::format("case '{}': the wave flume needs its wave maker (law = \"wave\") and its damping "
                                      "zone",
                                      c.name));
    for (const char* g : {"g2", "g4", "g6"})
      if (!has_gauge(g))
        throw AnalysisError(fmt::format("case '{}': no gauge '{}'; the wave flume is judged at 2, 4 and 6 wavelengths",
                                        c.name, g));
    return;
  }
  const NtnuRun* run = ntnu_run(case_name);
  if (!run) throw AnalysisError(fmt::format("no wave validation case '{}'", case_name));
  if (c.walls.size() < 2 || c.walls[1].rotation.law != MotionLawType::file ||
      fs::path(c.walls[1].rotation.file).filename() != run->record)
    throw AnalysisError(fmt::format("case '{}': the flap (wall[1]) must be driven by the record {}", c.name, run->record));
  for (const char* g : {"WP_1", "WP_2", "WP_3", "WP_4", "WP_6"})
    if (!has_gauge(g))
      throw AnalysisError(fmt::format("case '{}': no gauge '{}'; the NTNU flume is compared at its probes", c.name, g));
}

ValidationResult evaluate_wave_flume(const Case& c, const fs::path& run_dir, const ValidationBounds& b) {
  check_wave_case("wave_flume", c);
  const FlumeAnalysis a = analyze_flume(run_dir, c, {});
  const FlumeWave& w = a.wave;
  ValidationResult r;
  r.case_name = "wave_flume";
  r.title = "Regular waves along a flume against linear theory";
  r.resolution = fmt::format("H/dx = {:.3g} (dx = {:.4g} mm, H = {:.3g} m; L/dx = {:.0f})", w.height / c.dx, c.dx * 1e3,
                             w.height, w.wavelength / c.dx);
  r.settings = settings_of(c);
  double period_error = 0.0;
  for (double n : {2.0, 4.0, 6.0}) {
    const GaugeWaves* g = gauge_at(a, n);
    const std::string what = fmt::format("wave_flume: first-harmonic height error at {:g} wavelengths ({}), %", n, g->name);
    if (!g->harmonics || !g->zero_crossing) {
      r.checks.push_back({fmt::format("wave_flume.height_{:g}L", n), what, none, b.wave_height_percent});
      r.notes.push_back(fmt::format("{}: not measured: {}", g->name, g->note));
      period_error = none;
      continue;
    }
    r.checks.push_back({fmt::format("wave_flume.height_{:g}L", n), what,
                        100.0 * std::abs(2.0 * g->harmonics->amplitude[0] / w.height - 1.0), b.wave_height_percent});
    period_error = std::max(period_error, 100.0 * std::abs(g->zero_crossing->mean_period / w.period - 1.0));
    const Series theory = sampled_like(g->eta, g->window->t0, g->window->t1, [&](double t) {
      return 0.5 * w.height * std::cos(w.omega * t - g->theory_phase);
    });
    r.comparisons.push_back({fmt::format("eta_{}", g->name), fmt::format("surface elevation (m) at {}", g->name),
                             "linear theory, first order", fmt::format("{:.2f} <= t <= {:.2f} s", g->window->t0, g->window->t1),
                             compare(g->eta, theory, g->window->t0, g->window->t1)});
    r.figures.push_back({flume_gauge_plot(a, *g),
                         fmt::format("Gauge {}, {:.2f} wavelengths from the piston: sluice over linear theory in its "
                                     "steady window.",
                                     g->name, g->distance / w.wavelength),
                         0});
  }
  r.checks.push_back({"wave_flume.period", "wave_flume: zero-crossing period error at those gauges (largest), %",
                      period_error, b.wave_period_percent});
  r.checks.push_back({"wave_flume.reflection", "wave_flume: reflection coefficient Kr with the damping zone",
                      a.reflection ? a.reflection->coefficient : none, b.wave_reflection});
  if (a.decay)
    r.notes.push_back(fmt::format("Decay of the first harmonic: {:.2f} % per wavelength over {} gauges (reported, not "
                                  "bounded).",
                                  100.0 * a.decay->per_wavelength, a.decay->gauges));
  for (const auto& n : a.notes) r.notes.push_back(n);
  r.figures.push_back({flume_harmonics_plot(a), "The first and second harmonics along the flume.", 0});
  return r;
}

ValidationResult evaluate_ntnu_flume(const std::string& case_name, const Case& c, const fs::path& run_dir,
                                     const ValidationBounds& b) {
  check_wave_case(case_name, c);
  const FlumeAnalysis a = analyze_flume(run_dir, c, {});
  const NtnuRun* run = ntnu_run(case_name);
  ValidationResult r;
  r.case_name = case_name;
  r.title = fmt::format("NTNU flume, run {} (T = {:.4g} s): the probes against the laboratory's (Sundsdal et al. 2025)",
                        std::string(case_name).substr(5), a.wave.period);
  double height = 0.0;
  for (const auto& g : a.gauges)
    if (g.measured_harmonics) height = std::max(height, 2.0 * g.measured_harmonics->amplitude[0]);
  r.resolution = fmt::format("H/dx = {:.3g} (dx = {:.4g} mm, measured H = {:.3g} m; L/dx = {:.0f})", height / c.dx,
                             c.dx * 1e3, height, a.wave.wavelength / c.dx);
  r.settings = settings_of(c);
  std::size_t compared = 0;
  for (const auto& g : a.gauges) {
    if (!g.measured_harmonics) {
      r.notes.push_back(fmt::format("{} ({:.2f} m from the flap): not compared: {}", g.name, g.distance,
                                    g.note.empty() ? "no measurement" : g.note));
      continue;
    }
    ++compared;
    const double error = 100.0 * std::abs(g.harmonics->amplitude[0] / g.measured_harmonics->amplitude[0] - 1.0);
    constexpr double pi = std::numbers::pi;
    const double phase =
        std::abs(std::remainder(g.harmonics->phase[0] - g.measured_harmonics->phase[0], 2.0 * pi)) * 180.0 / pi;
    r.checks.push_back({fmt::format("{}.{}_amplitude", case_name, g.name),
                        fmt::format("{}: {} first-harmonic amplitude error against the probe, %", case_name, g.name),
                        error, b.ntnu_amplitude_percent});
    r.checks.push_back({fmt::format("{}.{}_phase", case_name, g.name),
                        fmt::format("{}: {} first-harmonic phase difference from the probe, degrees", case_name, g.name),
                        phase, b.ntnu_phase_degrees});
    r.comparisons.push_back({fmt::format("eta_{}", g.name), fmt::format("surface elevation (m) at {}", g.name),
                             fmt::format("NTNU run {}, {}", std::string(case_name).substr(5), g.name),
                             fmt::format("{:.2f} <= t <= {:.2f} s", g.window->t0, g.window->t1),
                             compare(g.eta, *g.measured, g.window->t0, g.window->t1)});
    r.figures.push_back({flume_gauge_plot(a, g),
                         fmt::format("Probe {}, {:.2f} m from the flap: sluice over the laboratory's record, the "
                                     "compared window shaded.",
                                     g.name, g.distance),
                         0});
  }
  if (compared == 0)
    r.checks.push_back({case_name + ".probes", case_name + ": probes compared with the laboratory", none, 0.0});
  r.notes.push_back(fmt::format("The flap follows the record {} from t = {:.3g} s (file time {:+.6g} s); the beach is a "
                                "damping zone, each window closing before its reflection of the steady waves returns.",
                                run->record, a.wave.start, run->time_offset));
  for (const auto& n : a.notes) r.notes.push_back(n);
  return r;
}

}  // namespace sluice::analysis
