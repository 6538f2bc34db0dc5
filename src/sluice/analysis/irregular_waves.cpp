#include "sluice/analysis/irregular_waves.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sluice/analysis/html_report.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/geometry/wave_theory.hpp"
#include "sluice/io/atomic_file.hpp"

namespace sluice::analysis {

namespace fs = std::filesystem;

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

struct IrregularMaker {
  std::size_t wall = 0;
  bool rotation = false;
  const MotionLawSpec* law = nullptr;
};

std::optional<IrregularMaker> irregular_maker(const Case& c) {
  for (std::size_t i = 0; i < c.walls.size(); ++i)
    for (bool rotation : {false, true}) {
      const MotionLawSpec& m = rotation ? c.walls[i].rotation : c.walls[i].translation;
      if (m.law == MotionLawType::wave && m.spectrum == WaveSpectrum::jonswap) return IrregularMaker{i, rotation, &m};
    }
  return std::nullopt;
}

}  // namespace

VarianceSpectrum variance_spectrum(const Series& eta, double t0, double t1, double f_max, int smooth) {
  std::vector<double> spacing;
  for (std::size_t j = 1; j < eta.size(); ++j)
    if (eta.t[j] >= t0 && eta.t[j] <= t1) spacing.push_back(eta.t[j] - eta.t[j - 1]);
  if (spacing.size() < 16)
    throw AnalysisError(fmt::format("fewer than 16 samples between t = {:.3g} and {:.3g} s", t0, t1));
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<long>(spacing.size() / 2), spacing.end());
  const double dt = spacing[spacing.size() / 2];
  const auto n = static_cast<std::size_t>(std::floor((t1 - t0) / dt + 1e-9));
  std::vector<double> y(n);
  double mean = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    y[j] = interpolate(eta, t0 + static_cast<double>(j) * dt).value_or(0.0);
    mean += y[j];
  }
  mean /= static_cast<double>(n);
  const double duration = static_cast<double>(n) * dt;
  std::vector<double> f, p;
  for (std::size_t k = 1; static_cast<double>(k) / duration <= f_max && k < n / 2; ++k) {
    double re = 0.0, im = 0.0;
    const double w = two_pi * static_cast<double>(k) / static_cast<double>(n);
    for (std::size_t j = 0; j < n; ++j) {
      re += (y[j] - mean) * std::cos(w * static_cast<double>(j));
      im -= (y[j] - mean) * std::sin(w * static_cast<double>(j));
    }
    f.push_back(static_cast<double>(k) / duration);
    p.push_back(2.0 * (re * re + im * im) * dt / static_cast<double>(n));  // one-sided, m^2/Hz
  }
  VarianceSpectrum s;
  s.f = f;
  const int half = std::max(0, smooth / 2);
  for (std::size_t k = 0; k < p.size(); ++k) {
    double sum = 0.0;
    int count = 0;
    for (int d = -half; d <= half; ++d) {
      const long q = static_cast<long>(k) + d;
      if (q < 0 || q >= static_cast<long>(p.size())) continue;
      sum += p[static_cast<std::size_t>(q)];
      ++count;
    }
    s.s.push_back(sum / count);
  }
  return s;
}

bool has_irregular_maker(const Case& c) { return irregular_maker(c).has_value(); }

IrregularAnalysis analyze_irregular_flume(const fs::path& run_dir, const Case& c) {
  const auto maker = irregular_maker(c);
  if (!maker) throw AnalysisError("the case has no wave maker with spectrum = \"jonswap\"");
  const MotionLawSpec& m = *maker->law;
  const Region& wall = c.walls[maker->wall];
  IrregularAnalysis a;
  a.maker = fmt::format("wall[{}].{} ({})", maker->wall, maker->rotation ? "rotation" : "translation", wall.name);
  a.significant_height = m.significant_height * m.gain;
  a.peak_period = m.peak_period;
  a.gamma = m.gamma;
  a.depth = m.depth;
  a.start = m.start;
  a.ramp_time = m.ramp * m.peak_period;
  a.maker_x = maker->rotation ? m.centre[0] : wall.max[0];
  const double g = std::sqrt(c.gravity[0] * c.gravity[0] + c.gravity[1] * c.gravity[1] + c.gravity[2] * c.gravity[2]);
  a.peak_group_velocity = waves::regular_wave(a.significant_height, a.peak_period, a.depth, g).group_velocity;
  const waves::IrregularSea sea = waves::jonswap_sea(m.significant_height, m.peak_period, m.gamma, m.components,
                                                     static_cast<std::uint64_t>(m.seed));
  a.repeat_period = 1.0 / sea.df;
  for (const auto& comp : sea.components) {
    a.target.f.push_back(comp.frequency);
    a.target.s.push_back(m.gain * m.gain * comp.amplitude * comp.amplitude / (2.0 * sea.df));
  }
  const std::optional<double> reflector =
      c.damps() ? std::nullopt : std::optional<double>(c.tank_size()[0] - a.maker_x);
  const double f_max = 4.0 / a.peak_period;
  for (const auto& p : c.probes) {
    if (p.type != ProbeType::gauge) continue;
    IrregularGauge gw;
    gw.name = p.name;
    gw.x = p.point[0];
    gw.distance = gw.x - a.maker_x;
    const fs::path file = run_dir / "probes" / (p.name + ".csv");
    std::error_code ec;
    if (!fs::exists(file, ec))
      throw AnalysisError(fmt::format("{}: no such file; expected gauge \"{}\"'s series", file.string(), p.name));
    Series s = read_csv_table(file).series("time", "height");
    if (s.size() < 2) throw AnalysisError(fmt::format("{}: fewer than two samples", file.string()));
    const double still = mean_before(s, a.start + std::max(0.0, gw.distance) / std::sqrt(g * a.depth));
    for (double& y : s.y) y -= still;
    gw.window = steady_window(gw.distance, a.start, a.ramp_time, a.peak_group_velocity, a.peak_period, s.t.back(),
                              reflector, 1.0, 4.0);
    if (!gw.window) {
      gw.note = "fewer than 4 peak periods of waves reach it before the run ends (or the reflection returns)";
    } else {
      double mean = 0.0, square = 0.0;
      std::size_t n = 0;
      for (std::size_t j = 0; j < s.size(); ++j)
        if (s.t[j] >= gw.window->t0 && s.t[j] <= gw.window->t1) {
          mean += s.y[j];
          square += s.y[j] * s.y[j];
          ++n;
        }
      mean /= static_cast<double>(n);
      gw.hm0 = 4.0 * std::sqrt(std::max(0.0, square / static_cast<double>(n) - mean * mean));
      try {
        gw.spectrum = variance_spectrum(s, gw.window->t0, gw.window->t1, f_max);
        const auto peak = std::max_element(gw.spectrum.s.begin(), gw.spectrum.s.end());
        gw.peak_period = 1.0 / gw.spectrum.f[static_cast<std::size_t>(peak - gw.spectrum.s.begin())];
      } catch (const AnalysisError& e) {
        gw.note = e.what();
      }
    }
    a.gauges.push_back(std::move(gw));
  }
  if (a.gauges.empty())
    throw AnalysisError("the case has no wave gauges ([[probe]] with type = \"gauge\"); expected at least one");
  a.notes.push_back(fmt::format(
      "the sea repeats every {:.4g} s; a window shorter than that samples it, and Hm0 from a window of N peak periods "
      "scatters by about 1/sqrt(N) of itself (Hs = 4 sqrt(m0) of the whole record exactly)",
      a.repeat_period));
  return a;
}

std::string irregular_table(const IrregularAnalysis& a) {
  std::string s = fmt::format("wave flume, irregular waves: {}\n", a.maker);
  s += fmt::format("  target     JONSWAP Hs = {:.4g} m, Tp = {:.4g} s, gamma = {:.3g} on h = {:.4g} m; peak group "
                   "velocity {:.4g} m/s\n",
                   a.significant_height, a.peak_period, a.gamma, a.depth, a.peak_group_velocity);
  s += fmt::format("  {:<10} {:>7} {:>13} {:>8} {:>8} {:>8} {:>8} {:>8}\n", "gauge", "x (m)", "window (s)", "Tp",
                   "Hm0", "Hm0 err", "Tp meas", "Tp err");
  for (const auto& g : a.gauges) {
    const bool ok = g.window && g.note.empty();
    s += fmt::format("  {:<10} {:>7.3f} {:>13} {:>8} {:>8} {:>8} {:>8} {:>8}{}\n", g.name, g.x,
                     g.window ? fmt::format("{:.2f}-{:.2f}", g.window->t0, g.window->t1) : std::string("-"),
                     g.window ? fmt::format("{:.1f}", g.window->periods(a.peak_period)) : std::string("-"),
                     ok ? fmt::format("{:.4f}", g.hm0) : std::string("-"),
                     ok ? fmt::format("{:+.1f}%", 100.0 * (g.hm0 / a.significant_height - 1.0)) : std::string("-"),
                     ok ? fmt::format("{:.3f}", g.peak_period) : std::string("-"),
                     ok ? fmt::format("{:+.1f}%", 100.0 * (g.peak_period / a.peak_period - 1.0)) : std::string("-"),
                     g.note.empty() ? "" : "  (" + g.note + ")");
  }
  s += "  (Tp: the window's length in peak periods; Hm0 = 4 sqrt(variance) over the window; Tp meas: the period of "
       "the measured spectrum's peak)\n";
  for (const auto& n : a.notes) s += "  note: " + n + "\n";
  return s;
}

void write_irregular_report(const IrregularAnalysis& a, const fs::path& run_dir, const fs::path& out_dir) {
  create_directories_or_throw(out_dir);
  std::string csv = "gauge,x,distance,t0,t1,hm0,peak_period,target_significant_height,target_peak_period\n";
  for (const auto& g : a.gauges) {
    const bool ok = g.window && g.note.empty();
    csv += fmt::format("{},{},{},{},{},{},{},{},{}\n", g.name, g.x, g.distance,
                       g.window ? fmt::format("{}", g.window->t0) : "", g.window ? fmt::format("{}", g.window->t1) : "",
                       ok ? fmt::format("{}", g.hm0) : "", ok ? fmt::format("{}", g.peak_period) : "",
                       a.significant_height, a.peak_period);
  }
  write_file_atomic(out_dir / "irregular.csv", csv);
  Plot p;
  p.title = "Variance spectra at the gauges and the maker's";
  p.x_label = "f (Hz)";
  p.y_label = "S (m^2/Hz)";
  PlotSeries target = curve(fmt::format("target JONSWAP, Hs = {:.3g} m", a.significant_height), a.target.f, a.target.s);
  target.dashed = true;
  p.series.push_back(target);
  for (const auto& g : a.gauges)
    if (g.window && g.note.empty() && !g.spectrum.f.empty()) p.series.push_back(curve(g.name, g.spectrum.f, g.spectrum.s));
  p.legend = Plot::LegendAt::top_right;
  const std::string svg = svg_plot(p);
  write_file_atomic(out_dir / "spectra.svg", svg);
  HtmlReport html("Wave flume, irregular waves: " + run_dir.string());
  html.paragraph(fmt::format("Wave maker: {}. Target: JONSWAP Hs = {:.4g} m, Tp = {:.4g} s, gamma = {:.3g} on h = "
                             "{:.4g} m.",
                             a.maker, a.significant_height, a.peak_period, a.gamma, a.depth));
  for (const auto& n : a.notes) html.paragraph("Note: " + n);
  std::vector<std::vector<std::string>> rows;
  for (const auto& g : a.gauges) {
    const bool ok = g.window && g.note.empty();
    rows.push_back({g.name, fmt::format("{:.3f}", g.x),
                    g.window ? fmt::format("{:.2f}-{:.2f}", g.window->t0, g.window->t1) : "-",
                    ok ? fmt::format("{:.4f}", g.hm0) : "-", ok ? fmt::format("{:.3f}", g.peak_period) : "-", g.note});
  }
  html.table({"gauge", "x (m)", "window (s)", "Hm0 (m)", "Tp (s)", "note"}, rows);
  html.figure(svg, "The gauges' variance spectra over their windows (Daniell-smoothed periodograms) and the maker's.");
  write_file_atomic(out_dir / "report.html", html.html());
}

}  // namespace sluice::analysis
