#include "sluice/render/render.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <utility>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/render/encoders.hpp"
#include "sluice/render/frame_renderer.hpp"
#include "sluice/render/render_error.hpp"
#include "sluice/render/run_frames.hpp"

namespace fs = std::filesystem;

namespace sluice::render {

namespace {

using FrameFiles = std::vector<std::pair<std::int64_t, fs::path>>;

// What the first pass keeps of a frame: its time and spacing, the extent of its particles, the
// extremes of its fluid values and a sample of them.
struct FrameSummary {
  double time = 0.0, dx = 0.0;
  Box box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  double vmin = std::numeric_limits<double>::infinity(), vmax = -std::numeric_limits<double>::infinity();
  std::vector<float> samples;
};

FrameSummary summarise(const FrameData& d, std::size_t max_samples) {
  FrameSummary s;
  s.time = d.time;
  s.dx = d.dx;
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    if (!std::isfinite(d.x[i]) || !std::isfinite(d.y[i])) continue;
    s.box.x0 = std::min<double>(s.box.x0, d.x[i]);
    s.box.x1 = std::max<double>(s.box.x1, d.x[i]);
    s.box.y0 = std::min<double>(s.box.y0, d.y[i]);
    s.box.y1 = std::max<double>(s.box.y1, d.y[i]);
    if (d.kind[i] == 0 && std::isfinite(d.value[i])) {
      ++fluid;
      s.vmin = std::min<double>(s.vmin, d.value[i]);
      s.vmax = std::max<double>(s.vmax, d.value[i]);
    }
  }
  const std::size_t stride = std::max<std::size_t>(1, (fluid + max_samples - 1) / std::max<std::size_t>(max_samples, 1));
  std::size_t k = 0;
  for (std::size_t i = 0; i < d.size(); ++i)
    if (d.kind[i] == 0 && std::isfinite(d.value[i]) && k++ % stride == 0) s.samples.push_back(d.value[i]);
  return s;
}

// The case's name, from the run's one .pvd file; empty if there is not exactly one.
std::string case_name_of(const fs::path& run_dir) {
  std::error_code ec;
  std::string name;
  int count = 0;
  for (const auto& entry : fs::directory_iterator(run_dir, ec))
    if (entry.path().extension() == ".pvd") {
      name = entry.path().stem().string();
      ++count;
    }
  return count == 1 ? name : std::string();
}

// Decimals of the time stamp: enough to tell frames `interval` apart, 2 to 4.
int decimals_for(double interval) {
  int d = 0;
  while (d < 4 && std::abs(interval * std::pow(10.0, d) - std::round(interval * std::pow(10.0, d))) >
                      1e-6 * std::max(1.0, interval * std::pow(10.0, d)))
    ++d;
  return std::clamp(d, 2, 4);
}

// Runs body(i) for every i, with ordered(i) called for i in order (in one thread at a time),
// rendering in parallel. Stops at the first error and rethrows the error of the lowest index.
template <class Body, class Ordered>
void parallel_in_order(std::size_t n, Body body, Ordered ordered) {
  std::atomic<bool> failed{false};
  std::exception_ptr error;
#pragma omp parallel for ordered schedule(static, 1)
  for (std::size_t i = 0; i < n; ++i) {
    std::exception_ptr mine;
    decltype(body(i)) result{};
    if (!failed.load()) {
      try {
        result = body(i);
      } catch (...) {
        mine = std::current_exception();
      }
    }
#pragma omp ordered
    {
      if (!error) {
        if (mine) error = mine;
        else {
          try {
            ordered(i, result);
          } catch (...) {
            error = std::current_exception();
          }
        }
        if (error) failed.store(true);
      }
    }
  }
  if (error) std::rethrow_exception(error);
}

// Requests that cannot be met whatever the frames hold.
void check_options(const RenderOptions& o) {
  if (o.fps < 1 || o.fps > 100) throw RenderError(fmt::format("--fps {}: give 1 to 100 frames per second", o.fps));
  if (o.format == Format::gif && o.fps > 50)
    throw RenderError(fmt::format("--fps {}: GIF frame delays are whole hundredths of a second and viewers slow "
                                  "down faster frames; use 50 or less, or --format mp4",
                                  o.fps));
  if (!o.times.empty() && o.format != Format::png)
    throw RenderError("--times picks snapshots: use it with --format png (or without --format)");
  if (o.range && !(o.range->lo < o.range->hi)) throw RenderError("--range: MIN must be less than MAX");
  if (o.format == Format::mp4) {
    require_ffmpeg();
    if (o.width % 2 != 0 || o.height % 2 != 0)
      throw RenderError(fmt::format("--size {}x{}: MP4 (H.264) needs an even width and height", o.width, o.height));
  }
}

// The first pass: every frame read, in parallel (so that a damaged one stops us before anything is
// written), for the domain to show and the colour range.
std::vector<FrameSummary> summarise_frames(const FrameFiles& files, Field field) {
  const std::size_t n = files.size();
  std::vector<FrameSummary> summaries(n);
  std::vector<std::exception_ptr> errors(n);
  const std::size_t max_samples = std::max<std::size_t>(1000, 4'000'000 / n);
#pragma omp parallel for schedule(dynamic)
  for (std::size_t i = 0; i < n; ++i) {
    try {
      summaries[i] = summarise(read_frame(files[i].second, field), max_samples);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return summaries;
}

Range colour_range(const RenderOptions& o, const FieldInfo& info, const std::vector<FrameSummary>& summaries) {
  if (o.range) return *o.range;
  std::vector<float> samples;
  for (const auto& s : summaries) samples.insert(samples.end(), s.samples.begin(), s.samples.end());
  return data_range(info, std::move(samples));
}

// The domain: the first frame's extent (walls and all), grown to take in particles that leave it
// later, but by no more than a quarter of its size each way (a particle flung far away must not
// shrink the picture), plus the particles' radius.
Box domain_box(const std::vector<FrameSummary>& summaries, const fs::path& first_file) {
  Box box = summaries.front().box;
  if (!(box.x1 >= box.x0 && box.y1 >= box.y0))
    throw FormatError(fmt::format("{}: no particle has a finite position", first_file.string()));
  const double grow = 0.25 * std::max(box.x1 - box.x0, box.y1 - box.y0);
  const Box limit{box.x0 - grow, box.y0 - grow, box.x1 + grow, box.y1 + grow};
  double dx = 0.0;
  for (const auto& s : summaries) {
    if (s.box.x1 < s.box.x0) continue;
    box.x0 = std::max(limit.x0, std::min(box.x0, s.box.x0));
    box.y0 = std::max(limit.y0, std::min(box.y0, s.box.y0));
    box.x1 = std::min(limit.x1, std::max(box.x1, s.box.x1));
    box.y1 = std::min(limit.y1, std::max(box.y1, s.box.y1));
    dx = std::max(dx, s.dx);
  }
  const double pad = 0.75 * dx;
  return {box.x0 - pad, box.y0 - pad, box.x1 + pad, box.y1 + pad};
}

// The median time between frames; 0 for a single frame.
double median_interval(const std::vector<FrameSummary>& summaries) {
  std::vector<double> gaps;
  for (std::size_t i = 1; i < summaries.size(); ++i) gaps.push_back(summaries[i].time - summaries[i - 1].time);
  if (gaps.empty()) return 0.0;
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  return gaps[gaps.size() / 2];
}

// The frames to draw: every frame, or the nearest one to each of `times` (RenderError if it is more
// than half a frame interval away).
std::vector<std::size_t> chosen_frames(const std::vector<double>& times, const std::vector<FrameSummary>& summaries) {
  const std::size_t n = summaries.size();
  std::vector<std::size_t> chosen;
  if (times.empty()) {
    for (std::size_t i = 0; i < n; ++i) chosen.push_back(i);
    return chosen;
  }
  const double interval = median_interval(summaries);
  for (const double t : times) {
    std::size_t best = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (std::abs(summaries[i].time - t) < std::abs(summaries[best].time - t)) best = i;
    if (std::abs(summaries[best].time - t) > 0.5 * interval + 1e-9 * std::max(1.0, std::abs(t)))
      throw RenderError(fmt::format("--times {}: no frame at t = {} s (the frames run from t = {} to {} s{})", t, t,
                                    summaries.front().time, summaries.back().time,
                                    interval > 0 ? fmt::format(", every {:.6g} s", interval) : ""));
    if (std::find(chosen.begin(), chosen.end(), best) == chosen.end()) chosen.push_back(best);
  }
  return chosen;
}

// The title (the case and the field), pointed ends for values beyond the range anywhere in the run,
// and time stamps with the decimals the frame interval needs.
Style style_for(const fs::path& run_dir, const FieldInfo& info, Range range,
                const std::vector<FrameSummary>& summaries) {
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for (const auto& s : summaries) {
    vmin = std::min(vmin, s.vmin);
    vmax = std::max(vmax, s.vmax);
  }
  const double tolerance = 1e-6 * (range.hi - range.lo);
  const std::size_t n = summaries.size();
  const double interval =
      n > 1 ? (summaries.back().time - summaries.front().time) / static_cast<double>(n - 1) : 0.1;
  Style style;
  const std::string case_name = case_name_of(run_dir);
  style.title = case_name.empty() ? std::string(info.title) : fmt::format("{} \u2014 {}", case_name, info.title);
  style.extend_low = vmin < range.lo - tolerance;
  style.extend_high = vmax > range.hi + tolerance;
  style.time_decimals = decimals_for(interval);
  return style;
}

// PNG pictures of the chosen frames: into OUTPUT_DIR/snapshots/ or -o's directory, or the one file -o
// names.
std::vector<fs::path> write_snapshots(const FrameRenderer& renderer, const FrameFiles& files,
                                      const std::vector<std::size_t>& chosen, const fs::path& run_dir,
                                      const RenderOptions& o) {
  fs::path dir = o.output.empty() ? run_dir / "snapshots" : o.output;
  std::optional<fs::path> single;
  if (o.output.extension() == ".png") {
    if (chosen.size() != 1)
      throw RenderError(fmt::format("-o {}: one file takes one picture, but {} frames are to be drawn; give a "
                                    "directory, or one time with --times",
                                    o.output.string(), chosen.size()));
    single = o.output;
    dir = o.output.parent_path();
  }
  if (!dir.empty()) create_directories_or_throw(dir);
  const std::string stem(field_info(o.field).name);
  std::vector<fs::path> paths(chosen.size());
  for (std::size_t k = 0; k < chosen.size(); ++k)
    paths[k] = single ? *single : dir / fmt::format("{}_{:06}.png", stem, files[chosen[k]].first);
  parallel_in_order(
      chosen.size(),
      [&](std::size_t k) {
        const FrameData d = read_frame(files[chosen[k]].second, o.field);
        write_png(paths[k], renderer.draw(d), renderer.palette());
        return 0;
      },
      [](std::size_t, int) {});
  return paths;
}

// The chosen frames as a GIF or MP4 at `path`, drawn in parallel and encoded in order. Returns the
// frame rate as played.
double write_animation(const FrameRenderer& renderer, const FrameFiles& files, const std::vector<std::size_t>& chosen,
                       const fs::path& path, const RenderOptions& o) {
  if (path.has_parent_path()) create_directories_or_throw(path.parent_path());
  const Layout& L = renderer.layout();
  std::unique_ptr<AnimationWriter> writer;
  double fps = o.fps;
  if (o.format == Format::gif) {
    const int delay = static_cast<int>(std::lround(100.0 / o.fps));
    writer = open_gif(path, L.width, L.height, renderer.palette(), delay);
    fps = 100.0 / delay;
  } else {
    writer = open_mp4(path, L.width, L.height, renderer.palette(), o.fps);
  }
  parallel_in_order(
      chosen.size(), [&](std::size_t k) { return renderer.draw(read_frame(files[chosen[k]].second, o.field)); },
      [&](std::size_t, const IndexedImage& image) { writer->add(image); });
  writer->finish();
  return fps;
}

}  // namespace

RenderResult render_run(const fs::path& run_dir, const RenderOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const FieldInfo& info = field_info(o.field);
  check_options(o);
  const FrameFiles files = list_frames(run_dir);
  const std::vector<FrameSummary> summaries = summarise_frames(files, o.field);
  const Range range = colour_range(o, info, summaries);
  const Box box = domain_box(summaries, files.front().second);
  const std::vector<std::size_t> chosen = chosen_frames(o.times, summaries);
  const FrameRenderer renderer(info, range, box, o.width, o.height, style_for(run_dir, info, range, summaries));

  RenderResult result;
  result.width = renderer.layout().width;
  result.height = renderer.layout().height;
  result.range = range;
  result.range_from_data = !o.range.has_value();
  result.field_title = info.title;
  result.unit = info.unit;
  result.frames = static_cast<int>(chosen.size());
  if (o.format == Format::png) {
    result.files = write_snapshots(renderer, files, chosen, run_dir, o);
    result.fps = 0.0;
  } else {
    const fs::path path =
        o.output.empty() ? run_dir / (std::string(info.name) + std::string(format_extension(o.format))) : o.output;
    result.fps = write_animation(renderer, files, chosen, path, o);
    result.files = {path};
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

std::string describe(const RenderResult& r) {
  const std::string range = fmt::format("{} from {:.4g} to {:.4g} {}{}", r.field_title, r.range.lo, r.range.hi, r.unit,
                                        r.range_from_data ? "" : " (--range)");
  if (r.files.size() == 1 && r.fps > 0)
    return fmt::format("wrote {}: {} frames, {}x{}, {:.4g} fps, {}; in {:.1f} s\n", r.files.front().string(), r.frames,
                       r.width, r.height, r.fps, range, r.seconds);
  std::string s = fmt::format("wrote {} PNG picture{} ({}x{}, {}) in {:.1f} s", r.files.size(),
                              r.files.size() == 1 ? "" : "s", r.width, r.height, range, r.seconds);
  if (r.files.size() <= 10)
    for (const auto& f : r.files) s += "\n  " + f.string();
  else
    s += fmt::format("\n  {} ... {}", r.files.front().string(), r.files.back().string());
  return s + "\n";
}

}  // namespace sluice::render
