#include "sluice/analysis/waves.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sluice/analysis/reference_data.hpp"

namespace sluice::analysis {

namespace {

// The top of particle i: its centre plus half a spacing.
double top_of(const Frame& f, const std::vector<double>& position, std::size_t i) {
  return position[2 * i + 1] + 0.5 * f.dx;
}

// The top of the highest fluid particle within `band` of the wall at x = width (0 if none): wider than
// one column, since the particles next to a wall do not stay on their initial lattice column.
double height_near_wall(const Frame& f, double width, double band) {
  const auto& position = f.position();
  const auto& kind = f.kind();
  double top = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (kind[i] == 0 && position[2 * i] >= width - band) top = std::max(top, top_of(f, position, i));
  return top;
}

}  // namespace

double SurfaceProfile::at(double x) const {
  if (top.empty()) return 0.0;
  const auto k = static_cast<long>(std::floor(x / column_width));
  return top[static_cast<std::size_t>(std::clamp<long>(k, 0, static_cast<long>(top.size()) - 1))];
}

SurfaceProfile surface_profile(const Frame& f, double width, double column_width) {
  if (!(column_width > 0.0) || !(width > 0.0))
    throw AnalysisError(fmt::format("surface profile: width {} and column width {} must be positive", width, column_width));
  SurfaceProfile s;
  s.column_width = column_width;
  s.top.assign(static_cast<std::size_t>(std::max(1.0, std::ceil(width / column_width - 1e-9))), 0.0);
  const auto& position = f.position();
  const auto& kind = f.kind();
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (kind[i] != 0) continue;
    const auto k = static_cast<long>(std::floor(position[2 * i] / column_width));
    const auto col = static_cast<std::size_t>(std::clamp<long>(k, 0, static_cast<long>(s.top.size()) - 1));
    s.top[col] = std::max(s.top[col], top_of(f, position, i));
  }
  return s;
}

Crest crest(const Frame& f) {
  const auto& position = f.position();
  const auto& kind = f.kind();
  Crest c;
  bool found = false;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (kind[i] != 0) continue;
    if (!found || top_of(f, position, i) > c.height) {
      c = {position[2 * i], top_of(f, position, i)};
      found = true;
    }
  }
  if (!found) throw AnalysisError(fmt::format("the frame at t = {} s holds no fluid particle", f.time));
  return c;
}

double centre_of_mass_x(const Frame& f) {
  const auto& position = f.position();
  const auto& kind = f.kind();
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (kind[i] == 0) {
      sum += position[2 * i];
      ++n;
    }
  if (n == 0) throw AnalysisError(fmt::format("the frame at t = {} s holds no fluid particle", f.time));
  return sum / static_cast<double>(n);
}

std::optional<double> wave_front(const Frame& f, const SurfaceProfile& initial, double threshold) {
  const auto& position = f.position();
  const auto& kind = f.kind();
  std::optional<double> front;
  for (std::size_t i = 0; i < f.size(); ++i) {
    if (kind[i] != 0) continue;
    const double x = position[2 * i];
    if (top_of(f, position, i) > initial.at(x) + threshold && (!front || x > *front)) front = x;
  }
  return front;
}

std::vector<Transit> find_transits(const Series& crest_x, double width) {
  std::vector<Transit> out;
  const double lo = 0.25 * width, hi = 0.75 * width, max_jump = width / 8.0;
  std::size_t i = 0;
  while (i < crest_x.size()) {
    if (crest_x.y[i] < lo || crest_x.y[i] > hi) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < crest_x.size() && crest_x.y[j + 1] >= lo && crest_x.y[j + 1] <= hi &&
           std::abs(crest_x.y[j + 1] - crest_x.y[j]) <= max_jump)
      ++j;
    const double moved = crest_x.y[j] - crest_x.y[i];
    if (j - i + 1 >= 3 && std::abs(moved) >= 0.25 * width) {
      Transit t;
      t.direction = moved > 0 ? 1 : -1;
      t.t_start = crest_x.t[i];
      t.t_end = crest_x.t[j];
      const LineFit fit = fit_line(crest_x, t.t_start, t.t_end);
      t.speed = std::abs(fit.slope);
      out.push_back(t);
    }
    i = j + 1;
  }
  return out;
}

double stoker_bore_speed_ratio(double depth_ratio) {
  if (!(depth_ratio >= 0.0) || depth_ratio > 0.9)
    throw AnalysisError(fmt::format(
        "Stoker's wet-bed solution is tabulated for downstream/upstream depth ratios 0 to 0.9; got {}", depth_ratio));
  const Table table = reference_table("stoker_wetbed_table.csv");
  Series s = table.series("hr_over_h0", "S_over_c0");
  // hr -> 0 is Ritter's dry bed, front speed 2 sqrt(g h0).
  s.t.insert(s.t.begin(), 0.0);
  s.y.insert(s.y.begin(), 2.0);
  return *interpolate(s, depth_ratio);
}

double first_mode_period(double width, double depth, double g) {
  const double k = std::numbers::pi / width;
  return 2.0 * std::numbers::pi / std::sqrt(g * k * std::tanh(k * depth));
}

WaveAnalysis start_wave_analysis(const Frame& first, double width, double g, const WaveOptions& options) {
  if (!(width > 0.0) || !(g > 0.0)) throw AnalysisError(fmt::format("tank width {} and gravity {} must be positive", width, g));
  WaveAnalysis a;
  a.width = width;
  a.dx = first.dx;
  std::size_t fluid = 0;
  for (const std::uint8_t kind : first.kind()) fluid += kind == 0;
  a.mean_depth = static_cast<double>(fluid) * first.dx * first.dx / width;
  a.initial_surface = surface_profile(first, width, first.dx);
  a.upstream_depth = a.initial_surface.top.front();
  a.downstream_depth = height_near_wall(first, width, 2.0 * first.dx);
  // A dam break has a step: a drop of the initial surface between two neighbouring columns that makes
  // up most of the difference between the walls (a tilted surface has none).
  const double step = a.upstream_depth - a.downstream_depth;
  double largest_drop = 0.0;
  for (std::size_t k = 0; k + 1 < a.initial_surface.top.size(); ++k)
    largest_drop = std::max(largest_drop, a.initial_surface.top[k] - a.initial_surface.top[k + 1]);
  a.dam_break = step > first.dx && largest_drop > 0.5 * step;
  a.front_threshold = options.front_threshold > 0.0 ? options.front_threshold : 0.1 * (a.dam_break ? step : a.mean_depth);
  a.shallow_water_speed = std::sqrt(g * a.mean_depth);
  a.linear_period = first_mode_period(width, a.mean_depth, g);
  a.shallow_water_period = 2.0 * width / a.shallow_water_speed;
  if (a.dam_break && a.downstream_depth / a.upstream_depth <= 0.9)
    a.stoker_speed = stoker_bore_speed_ratio(a.downstream_depth / a.upstream_depth) * std::sqrt(g * a.upstream_depth);
  else
    a.notes.push_back(a.dam_break ? "the depths on the two sides of the dam differ by less than 10%: Stoker's bore speed "
                                    "is not used"
                                  : "the initial surface has no dam-break step: Stoker's bore speed does not apply");

  a.transits_wanted = options.transits;
  return a;
}

void add_frame(WaveAnalysis& a, const Frame& f) {
  if (!a.time.empty() && f.time == a.time.back()) return;  // the same state written twice
  if (!a.time.empty() && !(f.time > a.time.back()))
    throw AnalysisError(fmt::format("frames out of order: t = {} s after t = {} s", f.time, a.time.back()));
  const Crest c = crest(f);
  a.time.push_back(f.time);
  a.crest_x.push_back(c.x);
  a.crest_height.push_back(c.height);
  a.centre_of_mass_x.push_back(centre_of_mass_x(f));
  const auto front = wave_front(f, a.initial_surface, a.front_threshold);
  a.front.push_back(front ? *front : std::nan(""));
  a.far_wall_height.push_back(height_near_wall(f, a.width, 2.0 * a.dx));
}

namespace {

// The front's speed on its first crossing of the middle half of the tank, before it reaches the
// far wall.
void measure_front_speed(WaveAnalysis& a) {
  const double width = a.width;
  Series first_transit;
  for (std::size_t i = 0; i < a.time.size(); ++i) {
    if (!std::isfinite(a.front[i])) continue;
    if (a.far_wall_arrival && a.time[i] > *a.far_wall_arrival) break;
    if (a.front[i] >= 0.25 * width && a.front[i] <= 0.75 * width) {
      first_transit.t.push_back(a.time[i]);
      first_transit.y.push_back(a.front[i]);
    }
  }
  if (first_transit.size() >= 3) a.front_fit = fit_line(first_transit, first_transit.t.front(), first_transit.t.back());
  else
    a.notes.push_back(fmt::format("the wave front crossed the middle half of the tank in {} frame{}; a front speed needs 3",
                                  first_transit.size(), first_transit.size() == 1 ? "" : "s"));
}

// The crest's transits, and their mean speed over the first transits_wanted of them.
void measure_crest_speed(WaveAnalysis& a) {
  a.transits = find_transits(Series{a.time, a.crest_x}, a.width);
  double sum = 0.0;
  for (const Transit& t : a.transits) {
    if (a.transits_averaged >= a.transits_wanted) break;
    sum += t.speed;
    ++a.transits_averaged;
  }
  if (a.transits_averaged > 0) a.mean_crest_speed = sum / a.transits_averaged;
  else a.notes.push_back("the crest never crossed the middle half of the tank: no crest speed");
  if (a.transits_averaged > 0 && a.transits_averaged < a.transits_wanted)
    a.notes.push_back(fmt::format("only {} crest transit{} found; the mean crest speed is over those", a.transits_averaged,
                                  a.transits_averaged == 1 ? "" : "s"));
}

// The sloshing period, from the centre of mass in two ways.
void measure_periods(WaveAnalysis& a) {
  const Series centre{a.time, a.centre_of_mass_x};
  try {
    a.period_zero_crossings = period_from_zero_crossings(centre);
  } catch (const AnalysisError& e) {
    a.notes.push_back(fmt::format("sloshing period (zero crossings): {}", e.what()));
  }
  try {
    a.period_autocorrelation = period_from_autocorrelation(centre);
  } catch (const AnalysisError& e) {
    a.notes.push_back(fmt::format("sloshing period (autocorrelation): {}", e.what()));
  }
}

}  // namespace

void finish_wave_analysis(WaveAnalysis& a) {
  if (a.time.size() < 2) throw AnalysisError(fmt::format("a wave analysis needs at least 2 frames; got {}", a.time.size()));
  const Series far_wall{a.time, a.far_wall_height};
  a.far_wall_arrival = first_rise_to(far_wall, a.downstream_depth + a.front_threshold);
  if (!a.far_wall_arrival)
    a.notes.push_back(fmt::format("the surface at the far wall never rose {:.3g} m above its initial height",
                                  a.front_threshold));
  measure_front_speed(a);
  measure_crest_speed(a);
  measure_periods(a);
}

WaveAnalysis analyze_waves(const std::vector<Frame>& frames, double width, double g, const WaveOptions& options) {
  if (frames.empty()) throw AnalysisError("a wave analysis needs at least 2 frames; got 0");
  WaveAnalysis a = start_wave_analysis(frames.front(), width, g, options);
  for (const Frame& f : frames) add_frame(a, f);
  finish_wave_analysis(a);
  return a;
}

std::vector<std::filesystem::path> list_npz_frames(const std::filesystem::path& output_dir) {
  namespace fs = std::filesystem;
  const fs::path dir = output_dir / "frames";
  std::error_code ec;
  if (!fs::is_directory(output_dir, ec))
    throw AnalysisError(fmt::format("{}: no such directory; expected a run's output directory", output_dir.string()));
  std::vector<fs::path> out;
  if (fs::is_directory(dir, ec))
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".npz") out.push_back(entry.path());
    }
  if (out.empty())
    throw AnalysisError(fmt::format("{}: no NumPy frames (frames/frame_NNNNNN.npz); run the case with npz among "
                                    "output.formats (the default)",
                                    output_dir.string()));
  std::sort(out.begin(), out.end());
  return out;
}

WaveAnalysis analyze_run(const std::filesystem::path& output_dir, const Case& c, const WaveOptions& options) {
  if (c.dimension != 2)
    throw AnalysisError(fmt::format("case '{}' is {}D; the wave analysis measures 2D runs", c.name, c.dimension));
  if (c.gravity[0] != 0.0 || !(c.gravity[1] < 0.0))
    throw AnalysisError(fmt::format("the wave analysis needs gravity straight down; the case has [{}, {}]", c.gravity[0],
                                    c.gravity[1]));
  auto read = [](const std::filesystem::path& path) {
    try {
      return read_npz_frame(path);
    } catch (const std::exception& e) {
      throw AnalysisError(e.what());
    }
  };
  // One frame in memory at a time: a long, fine run does not fit otherwise.
  const auto paths = list_npz_frames(output_dir);
  const Frame first = read(paths.front());
  WaveAnalysis a = start_wave_analysis(first, c.tank_width, -c.gravity[1], options);
  add_frame(a, first);
  for (std::size_t k = 1; k < paths.size(); ++k) add_frame(a, read(paths[k]));
  finish_wave_analysis(a);
  return a;
}

}  // namespace sluice::analysis
