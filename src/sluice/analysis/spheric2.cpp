// SPHERIC test 2 (Kleefsman et al. 2005) against the experiment: pressures P1-P4 on the obstacle's
// face and water levels H2, H4, in SI units over 0 <= t <= 6 s, with P1's impact time and peak.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "sluice/analysis/reference_data.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/analysis/validation.hpp"

namespace fs = std::filesystem;

namespace sluice::analysis {

namespace {

constexpr const char* spheric2_data = "spheric2_kleefsman2005_exp.csv";
constexpr double spheric2_height = 0.55;  // the water column's height, the scale of p* = p / (rho g H)
constexpr double spheric2_window = 6.0;   // s: the comparisons' window, 0 <= t <= 6 s

// The simulated series of a probe: time and the named column, scaled.
Series probe_column(const fs::path& run_dir, const std::string& probe, const std::string& column, double scale) {
  Series s = probe_series(run_dir, probe, column);
  for (double& y : s.y) y *= scale;
  return s;
}

Series scaled_column(const Table& data, const std::string& column, double scale) {
  Series s = data.series("t_s", column);
  for (double& y : s.y) y *= scale;
  return s;
}

// One probe's simulated curve against the experiment's, with the comparison over the window.
struct Signal {
  std::string probe, column, data_column, quantity, unit;
  double scale = 1.0;  // simulation and data to the shown unit
};

// The smallest and largest values with t <= t_max.
std::pair<double, double> extent_until(const Series& s, double t_max) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t i = 0; i < s.size() && s.t[i] <= t_max; ++i) lo = std::min(lo, s.y[i]), hi = std::max(hi, s.y[i]);
  return {lo, hi};
}

Figure signal_figure(const Signal& s, const Case& c, const Series& sim, const Series& data, const Table& table) {
  Plot plot;
  plot.title = fmt::format("SPHERIC test 2: {}", s.quantity);
  plot.x_label = "t (s)";
  plot.y_label = fmt::format("{} ({})", s.probe, s.unit);
  PlotSeries experiment = curve("Kleefsman et al. (2005), 1 ms samples", data.t, data.y);
  experiment.colour = "#999999";
  PlotSeries simulated = curve(fmt::format("sluice, H/dx = {:.3g}", spheric2_height / c.dx), sim.t, sim.y);
  simulated.colour = "#1f77b4";
  plot.series = {experiment, simulated};
  plot.legend = Plot::LegendAt::top_right;
  plot.x_range = {{0.0, spheric2_window}};
  // The axis spans the experiment's values (and 0) with a margin: the simulation's first-contact
  // spike, many times the measured peak, would otherwise flatten every other detail of the curves.
  const auto [data_lo, data_hi] = extent_until(data, spheric2_window);
  const auto [sim_lo, sim_hi] = extent_until(sim, spheric2_window);
  const double margin = 0.3 * (data_hi - data_lo);
  plot.y_range = {{std::min(0.0, data_lo) - margin, data_hi + margin}};
  std::string cut;
  if (sim_hi > plot.y_range->second || sim_lo < plot.y_range->first)
    cut = fmt::format(" The simulation's values run from {:.3g} to {:.3g} {}; those beyond the axis are cut at its edge.",
                      sim_lo, sim_hi, s.unit);
  return {plot,
          fmt::format("{} against the experiment (grey, the raw 1 ms record).{} Data: {}", s.quantity, cut,
                      table.comments.empty() ? std::string() : table.comments.front()),
          1};
}

// P1's impact: the first time it reaches a quarter of rho g H; and its peak.
void check_p1(ValidationResult& r, const Series& sim, const Series& data, double rho_g_h, const ValidationBounds& b) {
  const double level = impact_pressure_level * rho_g_h * 1e-3;  // kPa
  const auto impact_data = first_rise_to(data, level);
  const auto impact_sim = first_rise_to(sim, level);
  if (!impact_data) throw AnalysisError("the SPHERIC test 2 data never reach P1's impact level");
  const double miss = impact_sim ? std::abs(*impact_sim - *impact_data) : std::numeric_limits<double>::infinity();
  r.checks.push_back({"spheric2.p1_impact_time",
                      fmt::format("spheric2: |P1 impact time - data's| in s (P1 >= {:.2f} kPa; data {:.3f} s, sluice {})",
                                  level, *impact_data, impact_sim ? fmt::format("{:.3f} s", *impact_sim) : "never"),
                      miss, b.spheric2_impact});
  auto peak = [](const Series& s, double t_max) {
    std::size_t k = 0;
    for (std::size_t i = 0; i < s.size() && s.t[i] <= t_max; ++i)
      if (s.y[i] > s.y[k]) k = i;
    return std::pair{s.t[k], s.y[k]};
  };
  // The first impact's peak: within 0.3 s of the data's impact.
  const auto [t_data, p_data] = peak(data, *impact_data + 0.3);
  const auto [t_sim, p_sim] = peak(sim, *impact_data + 0.3);
  r.notes.push_back(fmt::format(
      "P1's first peak (within 0.3 s of the data's impact): sluice {:.2f} kPa at t = {:.3f} s, the experiment {:.2f} kPa "
      "at t = {:.3f} s. The experiment's record is raw (1 ms samples, sensor noise of about 0.1 kPa included).",
      p_sim, t_sim, p_data, t_data));
}

// When the collapse happens: the water's arrival at H2 (the level first 5 mm or more), and how far
// the fall of the reservoir's level at H4 runs behind the experiment's (the shift that best matches
// the two falls from their initial levels while the water runs out, 0.05 <= t <= 0.4 s, before it
// reaches the obstacle). A late P1 impact with H4 on time would be the front's doing (its speed, the
// floor); with H4 late by as much, it is the collapse's.
void note_collapse_timing(ValidationResult& r, const Series& h2_sim, const Series& h2_data, const Series& h4_sim,
                          const Series& h4_data) {
  constexpr double wet = 0.005;
  const auto h2_at_data = first_rise_to(h2_data, wet), h2_at_sim = first_rise_to(h2_sim, wet);
  const auto time = [](const std::optional<double>& t) { return t ? fmt::format("{:.3f} s", *t) : std::string("never"); };
  // Each level relative to its start (the data's as the mean over its first 10 ms of samples).
  const auto fall = [](Series s, double t_start) {
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < s.size() && (n == 0 || s.t[i] <= t_start); ++i) sum += s.y[i], ++n;
    const double start = sum / static_cast<double>(n);
    for (double& y : s.y) y -= start;
    return s;
  };
  std::string h4;
  if (!h4_sim.empty() && h4_sim.t.back() >= 0.4) {
    const Lag lag = best_lag(fall(h4_sim, 0.0), fall(h4_data, 0.01), 0.05, 0.4, 0.15, 0.001);
    h4 = fmt::format(" The reservoir's level at H4 falls {:.3f} s {} the experiment's (the shift that best matches the "
                     "two falls from their initial levels over 0.05 <= t <= 0.4 s, RMS {:.1f} mm there).",
                     std::abs(lag.shift), lag.shift >= 0.0 ? "after" : "before", lag.rms * 1e3);
  }
  r.notes.push_back(fmt::format("The collapse: the water reaches H2 (level {:g} mm or more) at {} (the experiment: {}).{}",
                                wet * 1e3, time(h2_at_sim), time(h2_at_data), h4));
}

}  // namespace

// The case must be the experiment's: a 3D tank 3.22 m x 1 m with the water column 0.55 m high.
void check_spheric2_case(const Case& c) {
  const bool tank = c.dimension == 3 && std::abs(c.tank_width - 3.22) < 1e-6 && std::abs(c.tank_depth - 1.0) < 1e-6;
  const bool water = c.water.size() == 1 && c.water[0].shape == Shape::box &&
                     std::abs(c.water[0].max[2] - spheric2_height) < 1e-6 && std::abs(c.water[0].min[0] - 1.992) < 1e-6;
  if (!tank || !water)
    throw AnalysisError(fmt::format("case '{}': the SPHERIC test 2 data are for a 3D tank 3.22 m x 1 m with one box of "
                                    "water from x = 1.992 m, 0.55 m high",
                                    c.name));
  if (c.gravity[0] != 0.0 || c.gravity[1] != 0.0 || !(c.gravity[2] < 0.0))
    throw AnalysisError(fmt::format("case '{}': the SPHERIC test 2 data assume gravity straight down along -z", c.name));
}

std::vector<ReferenceOverlay> spheric2_overlays(const Case& c) {
  check_spheric2_case(c);
  const Table table = reference_table(spheric2_data);
  std::vector<ReferenceOverlay> out;
  for (const auto& [probe, column, data_column] : {std::tuple{"P1", "pressure", "P1_Pa"}, {"P2", "pressure", "P2_Pa"},
                                                   {"P3", "pressure", "P3_Pa"}, {"P4", "pressure", "P4_Pa"},
                                                   {"H2", "height", "H2_m"}, {"H4", "height", "H4_m"}})
    out.push_back({"probes", probe, column, "Kleefsman et al. (2005)", false, scaled_column(table, data_column, 1.0)});
  return out;
}

ValidationResult evaluate_spheric2(const Case& c, const fs::path& run_dir, const ValidationBounds& b) {
  check_spheric2_case(c);
  const double g = -c.gravity[2];
  const double rho_g_h = c.rest_density * g * spheric2_height;
  ValidationResult r;
  r.case_name = "spheric2";
  r.title = "SPHERIC test 2 (Kleefsman et al. 2005): 3D dam break on a box obstacle";
  r.resolution = fmt::format("H/dx = {:.4g} (dx = {:.4g} mm, H = {:g} m)", spheric2_height / c.dx, c.dx * 1e3,
                             spheric2_height);
  r.settings = settings_of(c);
  const Table table = reference_table(spheric2_data);
  const std::vector<Signal> signals = {
      {"P1", "pressure", "P1_Pa", "pressure P1 on the obstacle, z = 0.021 m", "kPa", 1e-3},
      {"P2", "pressure", "P2_Pa", "pressure P2 on the obstacle, z = 0.061 m", "kPa", 1e-3},
      {"P3", "pressure", "P3_Pa", "pressure P3 on the obstacle, z = 0.101 m", "kPa", 1e-3},
      {"P4", "pressure", "P4_Pa", "pressure P4 on the obstacle, z = 0.141 m", "kPa", 1e-3},
      {"H2", "height", "H2_m", "water level H2 at x = 0.992 m", "m", 1.0},
      {"H4", "height", "H4_m", "water level H4 at x = 2.638 m", "m", 1.0}};
  std::map<std::string, std::pair<Series, Series>> levels;  // simulated and measured, by probe
  for (const Signal& s : signals) {
    const Series sim = probe_column(run_dir, s.probe, s.column, s.scale);
    const Series data = scaled_column(table, s.data_column, s.scale);
    const double t_end = std::min(spheric2_window, sim.t.back());
    r.comparisons.push_back({s.probe, fmt::format("{} ({})", s.quantity, s.unit), "Kleefsman et al. (2005)",
                             fmt::format("0 <= t <= {:g} s", t_end), compare(sim, data, 0.0, t_end)});
    r.figures.push_back(signal_figure(s, c, sim, data, table));
    if (s.probe == "P1") check_p1(r, sim, data, rho_g_h, b);
    if (s.column == "height") levels[s.probe] = {sim, data};
  }
  note_collapse_timing(r, levels["H2"].first, levels["H2"].second, levels["H4"].first, levels["H4"].second);
  r.notes.insert(r.notes.begin(),
                 fmt::format("Pressures in kPa (rho g H = {:.2f} kPa for H = 0.55 m), levels in m, time in s from the "
                             "release; RMS against every 1 ms sample of the experiment in the window. The pressure is "
                             "the run's probe reading at the sensor's centre; the level is the top of the highest "
                             "fluid particle within dx of the gauge's vertical line.",
                             rho_g_h * 1e-3));
  return r;
}

}  // namespace sluice::analysis
