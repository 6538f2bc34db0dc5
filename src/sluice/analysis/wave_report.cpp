#include "sluice/analysis/wave_report.hpp"

#include <fmt/format.h>

#include <cmath>

#include "sluice/analysis/html_report.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/io/atomic_file.hpp"

namespace sluice::analysis {

namespace {

struct Row {
  std::string quantity;
  double value;
  std::string unit;
};

std::vector<Row> summary_rows(const WaveAnalysis& w) {
  std::vector<Row> rows = {
      {"tank width L", w.width, "m"},
      {"mean initial depth h0 (fluid area / L)", w.mean_depth, "m"},
      {"initial depth at the left wall", w.upstream_depth, "m"},
      {"initial depth at the right wall", w.downstream_depth, "m"},
      {"shallow-water speed sqrt(g h0)", w.shallow_water_speed, "m/s"},
  };
  if (w.stoker_speed)
    rows.push_back({fmt::format("Stoker bore speed S (depth ratio {:.3g})", w.downstream_depth / w.upstream_depth),
                    *w.stoker_speed, "m/s"});
  rows.push_back({"front threshold above the initial surface", w.front_threshold, "m"});
  if (w.far_wall_arrival) rows.push_back({"wave reaches the far wall at", *w.far_wall_arrival, "s"});
  if (w.front_fit) {
    rows.push_back({"front speed, first transit (middle half of the tank)", std::abs(w.front_fit->slope), "m/s"});
    rows.push_back({"  / sqrt(g h0)", std::abs(w.front_fit->slope) / w.shallow_water_speed, ""});
    if (w.stoker_speed) rows.push_back({"  / Stoker S", std::abs(w.front_fit->slope) / *w.stoker_speed, ""});
  }
  for (std::size_t k = 0; k < w.transits.size(); ++k) {
    const Transit& t = w.transits[k];
    rows.push_back({fmt::format("crest transit {} ({}, t = {:.2f} to {:.2f} s) speed", k + 1,
                                t.direction > 0 ? "to the right" : "to the left", t.t_start, t.t_end),
                    t.speed, "m/s"});
  }
  if (w.mean_crest_speed) {
    rows.push_back({fmt::format("mean crest speed, first {} transit{}", w.transits_averaged, w.transits_averaged == 1 ? "" : "s"),
                    *w.mean_crest_speed, "m/s"});
    rows.push_back({"  / sqrt(g h0)", *w.mean_crest_speed / w.shallow_water_speed, ""});
    if (w.stoker_speed) rows.push_back({"  / Stoker S", *w.mean_crest_speed / *w.stoker_speed, ""});
  }
  if (w.period_zero_crossings)
    rows.push_back({fmt::format("sloshing period, zero crossings of the centre of mass ({})", w.period_zero_crossings->crossings),
                    w.period_zero_crossings->period, "s"});
  if (w.period_autocorrelation)
    rows.push_back({"sloshing period, autocorrelation of the centre of mass", *w.period_autocorrelation, "s"});
  rows.push_back({"linear first-mode period 2 pi / sqrt(g k tanh(k h0)), k = pi/L", w.linear_period, "s"});
  rows.push_back({"shallow-water period 2 L / sqrt(g h0)", w.shallow_water_period, "s"});
  return rows;
}

std::string csv_quote(const std::string& text) {
  std::string q = "\"";
  for (char ch : text) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

}  // namespace

std::string wave_table(const WaveAnalysis& w, const Case& c, const std::filesystem::path& run_dir) {
  std::string s = fmt::format("wave analysis of {} (case '{}', {} frames, t = {:g} to {:g} s, dx = {:g} m)\n",
                              run_dir.string(), c.name, w.time.size(), w.time.front(), w.time.back(), w.dx);
  for (const Row& r : summary_rows(w))
    s += fmt::format("  {:<72} {:>10.4g} {}\n", r.quantity, r.value, r.unit);
  for (const auto& n : w.notes) s += "  note: " + n + "\n";
  return s;
}

namespace {

std::string series_csv(const WaveAnalysis& w) {
  std::string s = "time,crest_x,crest_height,front,centre_of_mass_x,far_wall_height\n";
  for (std::size_t i = 0; i < w.time.size(); ++i)
    s += fmt::format("{},{},{},{},{},{}\n", w.time[i], w.crest_x[i], w.crest_height[i],
                     std::isfinite(w.front[i]) ? fmt::format("{}", w.front[i]) : std::string(), w.centre_of_mass_x[i],
                     w.far_wall_height[i]);
  return s;
}

std::string summary_csv(const WaveAnalysis& w) {
  std::string s = "quantity,value,unit\n";
  for (const Row& r : summary_rows(w)) s += fmt::format("{},{},{}\n", csv_quote(r.quantity), r.value, r.unit);
  return s;
}

// Crest and front positions, with the crest's transits shaded.
Plot positions_plot(const WaveAnalysis& w) {
  Plot plot;
  plot.title = "Crest and front positions";
  plot.x_label = "t (s)";
  plot.y_label = "x (m)";
  const PlotSeries crest_line = curve("crest (highest fluid point)", w.time, w.crest_x);
  // The front is a measure of the first transit: drawn until the wave reaches the far wall.
  std::vector<double> front_shown = w.front;
  for (std::size_t i = 0; i < w.time.size(); ++i)
    if (w.far_wall_arrival && w.time[i] > *w.far_wall_arrival) front_shown[i] = std::nan("");
  const PlotSeries front_line = curve(
      fmt::format("front (surface {:.3g} m above its initial level), first transit", w.front_threshold), w.time,
      front_shown);
  plot.series = {crest_line, front_line};
  for (const Transit& t : w.transits) plot.bands.push_back({t.t_start, t.t_end, fmt::format("{:.2f} m/s", t.speed)});
  plot.y_range = {{0.0, 1.3 * w.width}};  // room above the tank for the legend
  plot.legend = Plot::LegendAt::top_left;
  return plot;
}

Plot heights_plot(const WaveAnalysis& w) {
  Plot plot;
  plot.title = "Crest height";
  plot.x_label = "t (s)";
  plot.y_label = "height of the highest fluid point (m)";
  plot.series = {curve("crest height", w.time, w.crest_height),
                 curve("surface at the far wall", w.time, w.far_wall_height)};
  plot.legend = Plot::LegendAt::top_right;
  return plot;
}

// The centre of mass, and its mean with the period from the zero crossings about it.
Plot sloshing_plot(const WaveAnalysis& w) {
  Plot plot;
  plot.title = "Sloshing: horizontal centre of mass";
  plot.x_label = "t (s)";
  plot.y_label = "x of the centre of mass (m)";
  plot.series = {curve("centre of mass", w.time, w.centre_of_mass_x)};
  if (w.period_zero_crossings) {
    double mean = 0.0;
    for (double x : w.centre_of_mass_x) mean += x;
    mean /= static_cast<double>(w.centre_of_mass_x.size());
    PlotSeries m = curve(fmt::format("mean; period {:.3g} s (zero crossings)", w.period_zero_crossings->period),
                         {w.time.front(), w.time.back()}, {mean, mean});
    m.dashed = true;
    m.colour = "#999999";
    plot.series.push_back(m);
  }
  plot.legend = Plot::LegendAt::top_right;
  return plot;
}

struct WaveFigures {
  std::string positions, heights, sloshing;
};

std::string report_html(const WaveAnalysis& w, const Case& c, const std::filesystem::path& run_dir,
                        const WaveFigures& svg) {
  HtmlReport html(fmt::format("Wave analysis: {}", c.name));
  html.paragraph(fmt::format("Run {} (case '{}': {}), {} frames from t = {:g} s to {:g} s, dx = {:g} m. Produced by: "
                             "sluice analyze {}",
                             run_dir.string(), c.name, c.description, w.time.size(), w.time.front(), w.time.back(), w.dx,
                             run_dir.string()));
  std::vector<std::vector<std::string>> rows;
  for (const Row& r : summary_rows(w)) rows.push_back({r.quantity, fmt::format("{:.4g}", r.value), r.unit});
  html.table({"quantity", "value", "unit"}, rows);
  for (const auto& n : w.notes) html.paragraph("Note: " + n);
  html.figure(svg.positions,
              "The crest is the highest fluid point (its x); the front is the furthest fluid particle standing more "
              "than the threshold above the initial surface. Shaded: the crest's transits over the middle half of "
              "the tank, with the speed of a straight line through them.");
  html.figure(svg.heights, "Height of the highest fluid point (particle centre + dx/2), and the surface at the far wall "
                           "(highest fluid particle within 2 dx of it).");
  html.figure(svg.sloshing, "The horizontal centre of mass of the water, whose oscillation gives the sloshing period.");
  html.paragraph(
      "Definitions: h0 is the mean initial depth (fluid area over the tank width). Stoker's bore speed is for the "
      "initial depths at the two walls (data/validation/stoker_wetbed_table.csv, interpolated). Speeds are slopes of "
      "least-squares lines through the positions while in the middle half of the tank.");
  return html.html();
}

}  // namespace

void write_wave_report(const WaveAnalysis& w, const Case& c, const std::filesystem::path& run_dir,
                       const std::filesystem::path& out_dir) {
  create_directories_or_throw(out_dir);
  write_file_atomic(out_dir / "waves.csv", series_csv(w));
  write_file_atomic(out_dir / "summary.csv", summary_csv(w));
  WaveFigures svg;
  svg.positions = svg_plot(positions_plot(w));
  write_file_atomic(out_dir / "crest.svg", svg.positions);
  svg.heights = svg_plot(heights_plot(w));
  write_file_atomic(out_dir / "crest_height.svg", svg.heights);
  svg.sloshing = svg_plot(sloshing_plot(w));
  write_file_atomic(out_dir / "sloshing.svg", svg.sloshing);
  write_file_atomic(out_dir / "report.html", report_html(w, c, run_dir, svg));
}

}  // namespace sluice::analysis
