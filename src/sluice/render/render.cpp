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
#include "sluice/render/scene3d.hpp"

namespace fs = std::filesystem;

namespace sluice::render {

namespace {

using FrameFiles = std::vector<std::pair<std::int64_t, fs::path>>;

// What the first pass keeps of a frame: its time, spacing and dimension, the extent of its particles
// (z = 0 in 2D), the extremes of its fluid values and a sample of them, and how many particles lie in
// the slice's slab.
struct FrameSummary {
  double time = 0.0, dx = 0.0;
  int dimension = 2;
  Box3 box;
  double vmin = std::numeric_limits<double>::infinity(), vmax = -std::numeric_limits<double>::infinity();
  std::vector<float> samples;
  std::size_t in_slab = 0;
};

Vec3 position(const FrameData& d, std::size_t i) {
  return {d.x[i], d.y[i], d.z.empty() ? 0.0 : static_cast<double>(d.z[i])};
}

FrameSummary summarise(const FrameData& d, std::size_t max_samples, const std::optional<Slice>& slice) {
  FrameSummary s;
  s.time = d.time;
  s.dx = d.dx;
  s.dimension = d.dimension;
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const Vec3 p = position(d, i);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    s.box.add(p);
    if (slice && d.dimension == 3 && std::abs(p[slice->axis] - slice->value) < 0.5 * slice->thickness_for(d.dx))
      ++s.in_slab;
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
std::vector<FrameSummary> summarise_frames(const FrameFiles& files, Field field, const std::optional<Slice>& slice) {
  const std::size_t n = files.size();
  std::vector<FrameSummary> summaries(n);
  std::vector<std::exception_ptr> errors(n);
  const std::size_t max_samples = std::max<std::size_t>(1000, 4'000'000 / n);
#pragma omp parallel for schedule(dynamic)
  for (std::size_t i = 0; i < n; ++i) {
    try {
      summaries[i] = summarise(read_frame(files[i].second, field), max_samples, slice);
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
// shrink the picture).
Box3 run_box(const std::vector<FrameSummary>& summaries, const fs::path& first_file) {
  Box3 box = summaries.front().box;
  if (box.empty()) throw FormatError(fmt::format("{}: no particle has a finite position", first_file.string()));
  double size = 0.0;
  for (int a = 0; a < 3; ++a) size = std::max(size, box.hi[a] - box.lo[a]);
  const double grow = 0.25 * size;
  Box3 limit;
  for (int a = 0; a < 3; ++a) limit.lo[a] = box.lo[a] - grow, limit.hi[a] = box.hi[a] + grow;
  for (const auto& s : summaries) {
    if (s.box.empty()) continue;
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::max(limit.lo[a], std::min(box.lo[a], s.box.lo[a]));
      box.hi[a] = std::min(limit.hi[a], std::max(box.hi[a], s.box.hi[a]));
    }
  }
  return box;
}

double largest_dx(const std::vector<FrameSummary>& summaries) {
  double dx = 0.0;
  for (const auto& s : summaries) dx = std::max(dx, s.dx);
  return dx;
}

// A plane box grown by the particles' radius.
Box padded(Box b, double dx) {
  const double pad = 0.75 * dx;
  return {b.x0 - pad, b.y0 - pad, b.x1 + pad, b.y1 + pad};
}

// How a frame becomes what is drawn: as it is (2D), seen by the camera, or sliced; and the extent of
// the picture.
struct Drawing {
  std::optional<CameraScene> scene;
  std::optional<Slice> slice;
  Box world;
  std::string note;  // what the title says of the view
  [[nodiscard]] FrameData operator()(const FrameData& d) const {
    if (scene) return scene->view(d);
    if (slice) return slice_frame(d, *slice);
    return d;
  }
};

// The run's dimension; RenderError for camera or slice flags on a 2D run, or a run of both.
int run_dimension(const RenderOptions& o, const std::vector<FrameSummary>& summaries) {
  const int dim = summaries.front().dimension;
  for (const auto& s : summaries)
    if (s.dimension != dim)
      throw RenderError(fmt::format("the frames are {}D and {}D: a run is one or the other", dim, s.dimension));
  if (dim == 2 && o.camera)
    throw RenderError(fmt::format("{}: the run is 2D; the camera (--view, --azimuth, --elevation) draws 3D runs",
                                  o.camera_flag.empty() ? "--view" : o.camera_flag));
  if (dim == 2 && o.slice) throw RenderError("--slice: the run is 2D; slices are of 3D runs (a 2D run is drawn whole)");
  if (o.camera && o.slice)
    throw RenderError(fmt::format("{} and --slice: a slice is drawn flat, without a camera; give one or the other",
                                  o.camera_flag.empty() ? "--view" : o.camera_flag));
  return dim;
}

// RenderError for a slice outside the run or with no particle in its slab in any frame drawn.
void check_slice(const Slice& slice, const Box3& box, const std::vector<FrameSummary>& summaries,
                 const std::vector<std::size_t>& chosen) {
  const int a = slice.axis;
  if (slice.value < box.lo[a] || slice.value > box.hi[a])
    throw RenderError(fmt::format("--slice {}={:g}: outside the run, whose particles span {} = {:.4g} to {:.4g} m",
                                  "xyz"[a], slice.value, "xyz"[a], box.lo[a], box.hi[a]));
  std::size_t count = 0;
  for (const std::size_t i : chosen) count += summaries[i].in_slab;
  if (count == 0)
    throw RenderError(fmt::format("--slice {}={:g}: no particle lies within the slab {:.4g} m thick around it in the "
                                  "frames drawn (--thickness sets it)",
                                  "xyz"[a], slice.value, slice.thickness_for(summaries.front().dx)));
}

Drawing make_drawing(const RenderOptions& o, int dim, const std::vector<FrameSummary>& summaries,
                     const std::vector<std::size_t>& chosen, const FrameFiles& files) {
  const Box3 box = run_box(summaries, files.front().second);
  const double dx = largest_dx(summaries);
  Drawing d;
  if (dim == 2) {
    d.world = padded({box.lo[0], box.lo[1], box.hi[0], box.hi[1]}, dx);
  } else if (o.slice) {
    check_slice(*o.slice, box, summaries, chosen);
    d.slice = o.slice;
    d.world = padded(slice_box(box, o.slice->axis), dx);
    d.note = describe(*o.slice);
  } else {
    const Camera camera = o.camera.value_or(named_view(default_view_name()));
    d.scene.emplace(camera, box, read_frame(files.front().second, o.field));
    d.world = d.scene->world();
    d.note = describe(camera);
  }
  return d;
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
                const std::vector<FrameSummary>& summaries, const Drawing& drawing) {
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
  if (!drawing.note.empty()) {
    style.title += fmt::format(" ({})", drawing.note);
    style.short_title = fmt::format("{} ({})", info.title, drawing.note);
  }
  style.shaded = drawing.scene.has_value();
  style.extend_low = vmin < range.lo - tolerance;
  style.extend_high = vmax > range.hi + tolerance;
  style.time_decimals = decimals_for(interval);
  return style;
}

// PNG pictures of the chosen frames: into OUTPUT_DIR/snapshots/ or -o's directory, or the one file -o
// names.
std::vector<fs::path> write_snapshots(const FrameRenderer& renderer, const Drawing& drawing, const FrameFiles& files,
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
        const FrameData d = drawing(read_frame(files[chosen[k]].second, o.field));
        write_png(paths[k], renderer.draw(d), renderer.palette());
        return 0;
      },
      [](std::size_t, int) {});
  return paths;
}

// The chosen frames as a GIF or MP4 at `path`, drawn in parallel and encoded in order. Returns the
// frame rate as played.
double write_animation(const FrameRenderer& renderer, const Drawing& drawing, const FrameFiles& files,
                       const std::vector<std::size_t>& chosen, const fs::path& path, const RenderOptions& o) {
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
      chosen.size(), [&](std::size_t k) { return renderer.draw(drawing(read_frame(files[chosen[k]].second, o.field))); },
      [&](std::size_t, const IndexedImage& image) { writer->add(image); });
  writer->finish();
  return fps;
}

}  // namespace

RenderResult render_run(const fs::path& run_dir, const RenderOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  check_options(o);
  const FrameFiles files = list_frames(run_dir);
  const std::vector<FrameSummary> summaries = summarise_frames(files, o.field, o.slice);
  const int dim = run_dimension(o, summaries);
  const FieldInfo info = field_info(o.field, dim);
  const Range range = colour_range(o, info, summaries);
  const std::vector<std::size_t> chosen = chosen_frames(o.times, summaries);
  const Drawing drawing = make_drawing(o, dim, summaries, chosen, files);
  const FrameRenderer renderer(info, range, drawing.world, o.width, o.height,
                               style_for(run_dir, info, range, summaries, drawing));

  RenderResult result;
  result.width = renderer.layout().width;
  result.height = renderer.layout().height;
  result.range = range;
  result.range_from_data = !o.range.has_value();
  result.field_title = info.title;
  result.unit = info.unit;
  result.frames = static_cast<int>(chosen.size());
  if (o.format == Format::png) {
    result.files = write_snapshots(renderer, drawing, files, chosen, run_dir, o);
    result.fps = 0.0;
  } else {
    const fs::path path =
        o.output.empty() ? run_dir / (std::string(info.name) + std::string(format_extension(o.format))) : o.output;
    result.fps = write_animation(renderer, drawing, files, chosen, path, o);
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
