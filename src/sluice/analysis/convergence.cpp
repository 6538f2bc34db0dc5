#include "sluice/analysis/convergence.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "sluice/analysis/html_report.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/analysis/waves.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/directory_lock.hpp"
#include "sluice/simulation.hpp"

namespace fs = std::filesystem;

namespace sluice::analysis {

void compute_convergence_errors(ConvergenceStudy& study) {
  auto& levels = study.levels;
  if (levels.size() < 3) throw AnalysisError(fmt::format("a convergence study needs at least 3 spacings; got {}", levels.size()));
  const ConvergenceLevel& finest = levels.back();
  if (!finest.arrival)
    throw AnalysisError(fmt::format("in the finest run (dx = {:g} m) the wave never reached the far wall; run longer "
                                    "(--end)",
                                    finest.dx));
  for (std::size_t i = 0; i + 1 < levels.size(); ++i) {
    ConvergenceLevel& l = levels[i];
    if (l.arrival) l.arrival_error = std::abs(*l.arrival - *finest.arrival);
    try {
      l.front_error = compare(l.front, finest.front, 0.0, *finest.arrival).rms;
    } catch (const AnalysisError& e) {
      study.notes.push_back(fmt::format("dx = {:g} m: no front error: {}", l.dx, e.what()));
    }
  }
  for (std::size_t i = 0; i + 2 < levels.size(); ++i) {
    ConvergenceLevel& a = levels[i];
    const ConvergenceLevel& b = levels[i + 1];
    if (a.front_error > 0.0 && b.front_error > 0.0) a.front_order = observed_order(a.front_error, a.dx, b.front_error, b.dx);
    if (a.arrival_error > 0.0 && b.arrival_error > 0.0)
      a.arrival_order = observed_order(a.arrival_error, a.dx, b.arrival_error, b.dx);
  }
}

namespace {

std::string dx_name(double dx) { return fmt::format("dx_{:g}", dx); }

constexpr const char* far_wall_probe = "convergence_far_wall";

std::string number(double v, const char* format = "{:.4g}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(format), v) : std::string("-");
}

// Reference slopes through a point, for the log-log plot.
PlotSeries slope_line(double order, double dx_point, double error_point, double dx_lo, double dx_hi) {
  PlotSeries s = curve(fmt::format("order {:g}", order), {dx_lo, dx_hi},
                       {error_point * std::pow(dx_lo / dx_point, order), error_point * std::pow(dx_hi / dx_point, order)});
  s.dashed = true;
  s.colour = order == 1.0 ? "#aaaaaa" : "#666666";
  return s;
}

// The errors against the finest run on log-log axes, with slopes of order 1 and 2 through the finest
// point; no series if no error could be measured.
Plot errors_plot(const ConvergenceStudy& study) {
  Plot plot;
  plot.title = fmt::format("Convergence: {} (h/dx = {:g})", study.case_name, study.h_over_dx);
  plot.x_label = "dx (m)";
  plot.y_label = "error against the finest run";
  plot.log_x = plot.log_y = true;
  PlotSeries front = curve("front position, RMS (m)", {}, {}, PlotSeries::Style::line_and_markers);
  PlotSeries arrival = curve("far-wall arrival time (s)", {}, {}, PlotSeries::Style::line_and_markers);
  for (const auto& l : study.levels) {
    if (l.front_error > 0.0) {
      front.x.push_back(l.dx);
      front.y.push_back(l.front_error);
    }
    if (l.arrival_error > 0.0) {
      arrival.x.push_back(l.dx);
      arrival.y.push_back(l.arrival_error);
    }
  }
  if (!front.x.empty()) plot.series.push_back(front);
  if (!arrival.x.empty()) plot.series.push_back(arrival);
  if (!plot.series.empty()) {
    // Copied: the pushes below may reallocate the series.
    const double dx_point = plot.series.front().x.back(), error_point = plot.series.front().y.back();
    const double lo = dx_point / 1.5, hi = plot.series.front().x.front() * 1.5;
    plot.series.push_back(slope_line(1.0, dx_point, error_point, lo, hi));
    plot.series.push_back(slope_line(2.0, dx_point, error_point, lo, hi));
    plot.legend = Plot::LegendAt::top_left;
  }
  return plot;
}

// The wave front of every run, with the window of the front error shaded.
Plot fronts_plot(const ConvergenceStudy& study) {
  Plot plot;
  plot.title = fmt::format("Wave front over the first transit: {}", study.case_name);
  plot.x_label = "t (s)";
  plot.y_label = "x of the wave front (m)";
  for (const auto& l : study.levels) plot.series.push_back(curve(fmt::format("dx = {:g} m", l.dx), l.front.t, l.front.y));
  const double t_end = study.levels.back().arrival ? *study.levels.back().arrival : study.end_time;
  plot.bands = {{0.0, t_end, "error window"}};
  plot.x_range = {{0.0, std::min(study.end_time, 1.3 * t_end)}};
  plot.y_range = {{0.0, study.width}};
  plot.legend = Plot::LegendAt::bottom_right;
  return plot;
}

// errors_svg is empty when there is no errors plot.
std::string report_html(const ConvergenceStudy& study, const ConvergenceOptions& options, const std::string& errors_svg,
                        const std::string& fronts_svg) {
  HtmlReport html(fmt::format("Convergence study: {}", study.case_name));
  html.paragraph("Produced by: " + options.command_line);
  html.paragraph(fmt::format(
      "Each run uses h/dx = {:g}. Errors are against the finest run (dx = {:g} m). Front: RMS difference of the wave "
      "front position (furthest fluid particle standing {:.3g} m above the initial surface) at the frames (every {:.3g} "
      "s) from t = 0 to the finest run's far-wall arrival. Arrival: the first time the surface within 2 dx of the far "
      "wall stands {:.3g} m above its initial height, from a gauge sampled every step.",
      study.h_over_dx, study.levels.back().dx, study.front_threshold, study.frame_interval, study.front_threshold));
  std::vector<std::vector<std::string>> rows;
  for (const auto& l : study.levels)
    rows.push_back({fmt::format("{:g}", l.dx), std::to_string(l.particles), std::to_string(l.steps),
                    number(l.wall_seconds, "{:.1f}"), l.arrival ? number(*l.arrival) : "-", number(l.front_error),
                    number(l.front_order, "{:.2f}"), number(l.arrival_error), number(l.arrival_order, "{:.2f}")});
  html.table({"dx (m)", "particles", "steps", "wall time (s)", "far-wall arrival (s)", "front RMS error (m)",
              "order (front)", "arrival error (s)", "order (arrival)"},
             rows);
  for (const auto& n : study.notes) html.paragraph("Note: " + n);
  if (!errors_svg.empty())
    html.figure(errors_svg, "Errors against the finest run; dashed: slopes of order 1 and 2 for comparison.");
  html.figure(fronts_svg, "Wave-front position at each spacing; shaded: the window of the front error.");
  return html.html();
}

void write_outputs(const ConvergenceStudy& study, const ConvergenceOptions& options) {
  write_file_atomic(options.output_dir / "convergence.csv", convergence_csv(study));
  const Plot errors = errors_plot(study);
  const std::string errors_svg = errors.series.empty() ? std::string() : svg_plot(errors);
  if (!errors_svg.empty()) write_file_atomic(options.output_dir / "convergence.svg", errors_svg);
  const std::string fronts_svg = svg_plot(fronts_plot(study));
  write_file_atomic(options.output_dir / "fronts.svg", fronts_svg);
  write_file_atomic(options.output_dir / "report.html", report_html(study, options, errors_svg, fronts_svg));
}

// The mean depth h0 of the case's water (fluid area over the tank width), from its set-up at the
// coarsest spacing.
double mean_depth(const Case& base, double dx) {
  Case coarse = base;
  apply_overrides(coarse, {fmt::format("domain.dx={:.17g}", dx)});
  const Simulation setup(coarse);
  const double fluid = static_cast<double>(setup.diagnostics().fluid_particles);
  return fluid * coarse.dx * coarse.dx / coarse.tank_width;
}

// The case at spacing dx for the study's time span and frames, with a gauge at the far wall sampled
// every step.
Case level_case(const Case& base, double dx, const ConvergenceStudy& study) {
  Case c = base;
  apply_overrides(c, {fmt::format("domain.dx={:.17g}", dx), fmt::format("time.end={:.17g}", study.end_time),
                      fmt::format("output.interval={:.17g}", study.frame_interval), "output.formats=[\"npz\"]",
                      "output.checkpoint_interval=0"});
  Probe far_wall;
  far_wall.name = far_wall_probe;
  far_wall.type = ProbeType::gauge;
  far_wall.point = {c.tank_width, 0.0, 0.0};
  far_wall.band = 2.0 * dx;
  c.probes.push_back(far_wall);
  return c;
}

// Runs one spacing and measures its front and far-wall arrival. The first run fixes the study's front
// threshold, when the options leave it to the analysis, so that every spacing uses the same.
ConvergenceLevel run_level(const Case& c, double dx, ConvergenceStudy& study, const ConvergenceOptions& options,
                           std::ostream& log) {
  RunOptions run;
  run.output_dir = options.output_dir / dx_name(dx);
  run.threads = options.threads;
  run.progress = options.progress;
  log << fmt::format("convergence: running '{}' at dx = {:g} m to t = {:.3g} s into {}\n", c.name, dx,
                     study.end_time, run.output_dir.string())
      << std::flush;
  const RunResult rr = run_case(c, run, log);

  WaveOptions wave_options;
  wave_options.front_threshold = study.front_threshold;
  const WaveAnalysis w = analyze_run(run.output_dir, c, wave_options);
  if (!(study.front_threshold > 0.0)) study.front_threshold = w.front_threshold;

  ConvergenceLevel level;
  level.dx = dx;
  level.particles = rr.particles;
  level.fluid_particles = rr.final.fluid_particles;
  level.steps = rr.final.step;
  level.wall_seconds = rr.wall_seconds;
  for (std::size_t i = 0; i < w.time.size(); ++i)
    if (std::isfinite(w.front[i])) {
      level.front.t.push_back(w.time[i]);
      level.front.y.push_back(w.front[i]);
    }
  const Series gauge =
      read_csv_table(run.output_dir / "probes" / (std::string(far_wall_probe) + ".csv")).series("time", "height");
  level.arrival = first_rise_to(gauge, gauge.y.front() + study.front_threshold);
  log << fmt::format("convergence: dx = {:g} m: {} particles, {} steps, {:.1f} s; far-wall arrival {}\n", dx,
                     rr.particles, rr.final.step, rr.wall_seconds,
                     level.arrival ? fmt::format("t = {:.4f} s", *level.arrival) : std::string("not reached"))
      << std::flush;
  return level;
}

}  // namespace

ConvergenceStudy run_convergence(const Case& base, const ConvergenceOptions& options, std::ostream& log) {
  std::vector<double> spacings = options.dx;
  std::sort(spacings.begin(), spacings.end(), std::greater<>());
  if (spacings.size() < 3)
    throw AnalysisError(fmt::format("a convergence study needs at least 3 spacings; got {}", spacings.size()));
  if (base.dimension != 2)
    throw AnalysisError(fmt::format("case '{}' is {}D; the convergence study measures 2D waves", base.name,
                                    base.dimension));
  if (base.gravity[0] != 0.0 || !(base.gravity[1] < 0.0))
    throw AnalysisError("a convergence study measures a wave under gravity straight down");

  ConvergenceStudy study;
  study.case_name = base.name;
  study.width = base.tank_width;
  study.h_over_dx = base.h_over_dx;
  study.mean_depth = mean_depth(base, spacings.front());
  if (!(study.mean_depth > 0.0)) throw AnalysisError(fmt::format("case '{}' holds no water", base.name));
  const double crossing = base.tank_width / std::sqrt(-base.gravity[1] * study.mean_depth);
  study.end_time = options.end_time > 0.0 ? options.end_time : std::min(base.end_time, 1.2 * crossing);
  study.frame_interval = options.frame_interval > 0.0 ? options.frame_interval : crossing / 50.0;
  study.front_threshold = options.front_threshold;

  create_directories_or_throw(options.output_dir);
  const DirectoryLock lock(options.output_dir, "sluice convergence " + base.name);  // one study per directory
  for (double dx : spacings) study.levels.push_back(run_level(level_case(base, dx, study), dx, study, options, log));
  compute_convergence_errors(study);
  write_outputs(study, options);
  return study;
}

std::string convergence_csv(const ConvergenceStudy& study) {
  std::string s = "dx,particles,fluid_particles,steps,wall_seconds,arrival,front_error,front_order,arrival_error,"
                  "arrival_order\n";
  auto v = [](double x) { return std::isfinite(x) ? fmt::format("{}", x) : std::string(); };
  for (const auto& l : study.levels)
    s += fmt::format("{},{},{},{},{},{},{},{},{},{}\n", l.dx, l.particles, l.fluid_particles, l.steps, l.wall_seconds,
                     l.arrival ? v(*l.arrival) : std::string(), v(l.front_error), v(l.front_order), v(l.arrival_error),
                     v(l.arrival_order));
  return s;
}

std::string convergence_table(const ConvergenceStudy& study) {
  std::string s = fmt::format(
      "convergence of '{}' (h/dx = {:g}, front threshold {:.3g} m, frames every {:.3g} s, runs to t = {:.3g} s)\n",
      study.case_name, study.h_over_dx, study.front_threshold, study.frame_interval, study.end_time);
  s += fmt::format("{:>10} {:>10} {:>8} {:>9} {:>12} {:>14} {:>7} {:>14} {:>7}\n", "dx (m)", "particles", "steps",
                   "wall (s)", "arrival (s)", "front RMS (m)", "order", "arrival err(s)", "order");
  for (const auto& l : study.levels)
    s += fmt::format("{:>10g} {:>10} {:>8} {:>9.1f} {:>12} {:>14} {:>7} {:>14} {:>7}\n", l.dx, l.particles, l.steps,
                     l.wall_seconds, l.arrival ? number(*l.arrival) : "-", number(l.front_error),
                     number(l.front_order, "{:.2f}"), number(l.arrival_error), number(l.arrival_order, "{:.2f}"));
  s += "(errors against the finest run; order p = log(e1/e2)/log(dx1/dx2) between consecutive spacings)\n";
  for (const auto& n : study.notes) s += "note: " + n + "\n";
  return s;
}

}  // namespace sluice::analysis
