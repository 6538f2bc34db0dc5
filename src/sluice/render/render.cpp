#include "sluice/render/render.hpp"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <map>
#include <numbers>
#include <regex>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/render/encoders.hpp"

namespace fs = std::filesystem;

namespace sluice::render {

// ---------------------------------------------------------------------------------------------
// Fields and option parsing

namespace {

const std::array<FieldInfo, 5> fields = {{
    {Field::vx, "vx", "horizontal velocity vx", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::vy, "vy", "vertical velocity vy", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::speed, "speed", "speed |v|", "m/s", 1.0, Colormap::viridis, false},
    {Field::pressure, "pressure", "pressure p", "kPa", 1e-3, Colormap::viridis, false},
    {Field::density, "density", "density \u03C1", "kg/m\u00B3", 1.0, Colormap::viridis, false},
}};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> parse_int(std::string_view s) {
  s = trim(s);
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

const FieldInfo& field_info(Field field) {
  for (const auto& f : fields)
    if (f.field == field) return f;
  throw std::logic_error("field_info: unknown field");
}

std::string field_names() {
  std::string s;
  for (const auto& f : fields) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

Field parse_field(std::string_view text) {
  for (const auto& f : fields)
    if (f.name == text) return f.field;
  throw RenderError(fmt::format("unknown field '{}'; the fields are {}", text, field_names()));
}

Format parse_format(std::string_view text) {
  if (text == "gif") return Format::gif;
  if (text == "mp4") return Format::mp4;
  if (text == "png") return Format::png;
  throw RenderError(fmt::format("unknown format '{}'; the formats are gif, mp4, png", text));
}

std::string_view format_extension(Format format) {
  switch (format) {
    case Format::gif: return ".gif";
    case Format::mp4: return ".mp4";
    case Format::png: return ".png";
  }
  return "";
}

Range parse_range(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos || text.find(':', colon + 1) != std::string_view::npos)
    throw RenderError(fmt::format("--range '{}': expected MIN:MAX, e.g. 0:5 or -2:2", text));
  const auto lo = parse_double(text.substr(0, colon));
  const auto hi = parse_double(text.substr(colon + 1));
  if (!lo || !hi) throw RenderError(fmt::format("--range '{}': MIN and MAX must be numbers, e.g. 0:5 or -2:2", text));
  if (!(*lo < *hi)) throw RenderError(fmt::format("--range '{}': MIN must be less than MAX", text));
  return {*lo, *hi};
}

std::pair<int, int> parse_size(std::string_view text) {
  const auto x = text.find_first_of("xX");
  const auto w = x == std::string_view::npos ? std::nullopt : parse_int(text.substr(0, x));
  const auto h = x == std::string_view::npos ? std::nullopt : parse_int(text.substr(x + 1));
  if (!w || !h) throw RenderError(fmt::format("--size '{}': expected WIDTHxHEIGHT in pixels, e.g. 1280x720", text));
  if (*w < 160 || *h < 120 || *w > 8192 || *h > 8192)
    throw RenderError(fmt::format("--size '{}': width must be 160 to 8192 and height 120 to 8192 pixels", text));
  return {*w, *h};
}

std::vector<double> parse_times(std::string_view text) {
  std::vector<double> times;
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const auto item = text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const auto t = parse_double(item);
    if (!t || *t < 0.0)
      throw RenderError(fmt::format("--times '{}': '{}' is not a time in seconds (expected t1,t2,..., e.g. 0,1.5,3)",
                                    text, trim(item)));
    times.push_back(*t);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return times;
}

// ---------------------------------------------------------------------------------------------
// Ticks

std::vector<double> nice_ticks(Range range, int max_ticks) {
  max_ticks = std::max(max_ticks, 2);
  const double span = range.hi - range.lo;
  if (!(span > 0.0) || !std::isfinite(span)) return {range.lo};
  const int e0 = static_cast<int>(std::floor(std::log10(span / max_ticks))) - 1;
  for (int e = e0; e < e0 + 6; ++e)
    for (const double m : {1.0, 2.0, 2.5, 5.0}) {
      const double step = m * std::pow(10.0, e);
      const double first = std::ceil(range.lo / step - 1e-9), last = std::floor(range.hi / step + 1e-9);
      const double count = last - first + 1;
      if (count > max_ticks) continue;
      std::vector<double> ticks;
      for (double k = first; k <= last; k += 1.0) {
        const double v = k * step;
        ticks.push_back(v == 0.0 ? 0.0 : v);  // no -0
      }
      return ticks;
    }
  return {range.lo, range.hi};
}

std::string tick_label(double value, double step) {
  int decimals = 0;
  step = std::abs(step);
  while (decimals < 6) {
    const double scaled = step * std::pow(10.0, decimals);
    if (scaled > 0 && std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
    ++decimals;
  }
  std::string s = fmt::format("{:.{}f}", value, decimals);
  if (s.front() == '-') {
    if (s.find_first_not_of("-0.") == std::string::npos) return s.substr(1);  // "-0.0"
    s = "\u2212" + s.substr(1);                                                // a real minus sign
  }
  return s;
}

// ---------------------------------------------------------------------------------------------
// Frames and ranges

FrameData extract(const Frame& frame, Field field) {
  if (frame.dimension != 2)
    throw RenderError(fmt::format("the frame at t = {} s is {}D; sluice render draws 2D runs (pictures of 3D runs "
                                  "are not implemented yet: open the .pvd in ParaView)",
                                  frame.time, frame.dimension));
  const FieldInfo& info = field_info(field);
  const std::size_t n = frame.size();
  FrameData d;
  d.time = frame.time;
  d.dx = frame.dx;
  d.x.resize(n);
  d.y.resize(n);
  d.value.resize(n);
  d.kind = frame.kind();
  const auto& position = frame.position();
  const auto& velocity = frame.velocity();
  const auto& pressure = frame.pressure();
  const auto& density = frame.density();
  for (std::size_t i = 0; i < n; ++i) {
    d.x[i] = static_cast<float>(position[2 * i]);
    d.y[i] = static_cast<float>(position[2 * i + 1]);
    const double vx = velocity[2 * i], vy = velocity[2 * i + 1];
    double v = 0.0;
    switch (field) {
      case Field::vx: v = vx; break;
      case Field::vy: v = vy; break;
      case Field::speed: v = std::hypot(vx, vy); break;
      case Field::pressure: v = pressure[i]; break;
      case Field::density: v = density[i]; break;
    }
    d.value[i] = static_cast<float>(v * info.scale);
  }
  return d;
}

namespace {

double quantile(std::vector<float>& v, double q) {
  const auto k = static_cast<std::size_t>(std::llround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

Range data_range(const FieldInfo& info, std::vector<float> samples) {
  std::erase_if(samples, [](float v) { return !std::isfinite(v); });
  Range r{0.0, 1.0};
  if (!samples.empty()) {
    if (info.is_signed) {
      for (float& v : samples) v = std::abs(v);
      const double m = quantile(samples, 0.999);
      r = {-m, m};
    } else if (info.field == Field::speed) {
      r = {0.0, quantile(samples, 0.999)};
    } else {
      r.lo = quantile(samples, 0.001);
      r.hi = quantile(samples, 0.999);
    }
  }
  const double size = std::max({1.0, std::abs(r.lo), std::abs(r.hi)});
  if (r.hi - r.lo <= 1e-9 * size) {  // a uniform field: any range that contains it
    if (info.is_signed) r = {-1.0, 1.0};
    else if (info.field == Field::speed) r = {0.0, 1.0};
    else {
      const double half = std::max(1e-3 * std::abs(r.lo), 0.5);
      r = {r.lo - half, r.lo + half};
    }
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// Drawing

namespace {

constexpr int text_darkness = Palette::grey_levels - 1;
constexpr int frame_darkness = 22;  // colour-bar outline and ticks

int title_px_for(int width, int height) {
  if (width <= 0 || height <= 0) return 16;
  return std::clamp(static_cast<int>(std::lround(std::min(width / 62.0, height / 30.0))), 10, 40);
}
int label_px_for(int title_px) { return std::max(9, static_cast<int>(std::lround(0.85 * title_px))); }

}  // namespace

FrameRenderer::FrameRenderer(const FieldInfo& field, Range range, Box world, int width, int height, Style style,
                             const fs::path& font_file)
    : field_(field), range_(range), style_(std::move(style)), palette_(Palette::for_map(field.map)),
      title_font_(font_file, title_px_for(width, height)),
      label_font_(font_file, label_px_for(title_px_for(width, height))) {
  if (!(range.lo < range.hi)) throw RenderError("the colour range is empty");
  const double ww = world.x1 - world.x0, wh = world.y1 - world.y0;
  if (!(ww > 0 && wh > 0 && std::isfinite(ww) && std::isfinite(wh))) throw RenderError("the domain to draw is empty");

  Layout& L = layout_;
  const int px = title_font_.pixel_size();
  L.font_px = px;
  const int margin = std::max(6, static_cast<int>(std::lround(0.75 * px)));
  const int top = static_cast<int>(std::lround(2.3 * px));
  const int bar_w = std::max(10, static_cast<int>(std::lround(1.1 * px)));
  const int gap = px;
  const int tick_len = std::max(3, static_cast<int>(std::lround(0.35 * px)));
  const int label_gap = std::max(3, static_cast<int>(std::lround(0.3 * px)));
  int label_w = 0;
  for (int n = 2; n <= 10; ++n) {
    const auto ticks = nice_ticks(range, n);
    const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
    for (double t : ticks) label_w = std::max(label_w, label_font_.text_width(tick_label(t, step)));
  }
  label_w = std::max(label_w, label_font_.text_width(field.unit) - bar_w - tick_len - label_gap);
  const int panel_w = gap + bar_w + tick_len + label_gap + label_w + margin;
  const int min_bar = 12 * label_font_.pixel_size();

  int area_w = 0, area_h = 0;
  double s = 0.0;
  if (width <= 0 || height <= 0) {  // default: about 900 x 600 pixels for the domain
    s = std::min(900.0 / ww, 600.0 / wh);
    area_w = std::max(1, static_cast<int>(std::lround(ww * s)));
    area_h = std::max(static_cast<int>(std::lround(wh * s)), min_bar);
    width = margin + area_w + panel_w;
    height = top + area_h + margin;
    width += width % 2;  // even sizes suit video encoders
    height += height % 2;
  } else {
    area_w = width - margin - panel_w;
    area_h = height - top - margin;
    if (area_w < 40 || area_h < 40)
      throw RenderError(fmt::format("--size {}x{}: too small for the picture, its colour bar and labels", width, height));
    s = std::min(area_w / ww, area_h / wh);
  }
  L.width = width;
  L.height = height;
  const int plot_w = std::clamp(static_cast<int>(std::lround(ww * s)), 1, area_w);
  const int plot_h = std::clamp(static_cast<int>(std::lround(wh * s)), 1, area_h);
  L.plot.x0 = margin + (area_w - plot_w) / 2;
  L.plot.y0 = top + (area_h - plot_h) / 2;
  L.plot.x1 = L.plot.x0 + plot_w;
  L.plot.y1 = L.plot.y0 + plot_h;
  L.scale = s;
  // The shown world box fills the plot exactly, centred on the requested one.
  const double cx = 0.5 * (world.x0 + world.x1), cy = 0.5 * (world.y0 + world.y1);
  L.world = {cx - 0.5 * plot_w / s, cy - 0.5 * plot_h / s, cx + 0.5 * plot_w / s, cy + 0.5 * plot_h / s};

  const int bar_h = std::max(plot_h, std::min(area_h, min_bar));
  L.bar.x0 = L.plot.x1 + gap;
  L.bar.x1 = L.bar.x0 + bar_w;
  L.bar.y0 = std::clamp((L.plot.y0 + L.plot.y1) / 2 - bar_h / 2, top, top + area_h - bar_h);
  L.bar.y1 = L.bar.y0 + bar_h;
  const int tri_h = static_cast<int>(std::lround(0.9 * bar_w));
  if (style_.extend_high) L.bar.y0 += tri_h + 1;
  if (style_.extend_low) L.bar.y1 -= tri_h + 1;
  if (L.bar.height() < 8) throw RenderError(fmt::format("--size {}x{}: too small for the colour bar", width, height));
  draw_static();
}

int FrameRenderer::title_baseline() const {
  // Just above the plot, which is centred in the room a given --size leaves.
  const int px = layout_.font_px;
  return std::max(static_cast<int>(std::lround(1.5 * px)), layout_.plot.y0 - static_cast<int>(std::lround(0.8 * px)));
}

void FrameRenderer::draw_static() {
  const Layout& L = layout_;
  base_ = IndexedImage(L.width, L.height, Palette::white);
  const int px = L.font_px;
  const Rect& bar = L.bar;
  const int bar_h = bar.height();

  // Title, if it fits beside the time stamp.
  const int time_w = title_font_.text_width(fmt::format("t = {:.{}f} s", 8888.0, style_.time_decimals));
  const int room = L.plot.width() - time_w - px;
  const int baseline = title_baseline();
  for (const std::string& title : {style_.title, std::string(field_.title)})
    if (!title.empty() && title_font_.text_width(title) <= room) {
      title_font_.draw(base_, L.plot.x0, baseline, title, text_darkness);
      break;
    }

  // Colour bar, low values at the bottom, with a one-pixel outline.
  fill_rect(base_, {bar.x0 - 1, bar.y0 - 1, bar.x1 + 1, bar.y1 + 1}, Palette::grey(frame_darkness));
  for (int y = bar.y0; y < bar.y1; ++y) {
    const double t = bar_h > 1 ? static_cast<double>(bar.y1 - 1 - y) / (bar_h - 1) : 0.5;
    fill_rect(base_, {bar.x0, y, bar.x1, y + 1}, Palette::map_index(t));
  }
  const double tri_h = std::lround(0.9 * bar.width());
  const double mid = 0.5 * (bar.x0 + bar.x1);
  if (style_.extend_high)
    fill_triangle(base_, {double(bar.x0), double(bar.y0)}, {double(bar.x1), double(bar.y0)}, {mid, bar.y0 - 1 - tri_h},
                  Palette::map_index(1.0));
  if (style_.extend_low)
    fill_triangle(base_, {double(bar.x0), double(bar.y1)}, {double(bar.x1), double(bar.y1)}, {mid, bar.y1 + 1 + tri_h},
                  Palette::map_index(0.0));

  // Ticks and their labels.
  const int label_px = label_font_.pixel_size();
  const int tick_len = std::max(3, static_cast<int>(std::lround(0.35 * px)));
  const int label_gap = std::max(3, static_cast<int>(std::lround(0.3 * px)));
  const int tick_w = px >= 24 ? 2 : 1;
  const int max_ticks = std::clamp(static_cast<int>(bar_h / (4.0 * label_px)), 2, 8);
  const auto ticks = nice_ticks(range_, max_ticks);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
  for (const double v : ticks) {
    const double f = (v - range_.lo) / (range_.hi - range_.lo);
    const int y = bar.y1 - 1 - static_cast<int>(std::lround(f * (bar_h - 1)));
    fill_rect(base_, {bar.x1, y - tick_w / 2, bar.x1 + tick_len, y - tick_w / 2 + tick_w}, Palette::grey(frame_darkness));
    label_font_.draw(base_, bar.x1 + tick_len + label_gap, y + label_font_.digit_height() / 2, tick_label(v, step),
                     text_darkness);
  }
  // The unit above the bar.
  const int top_outer = bar.y0 - (style_.extend_high ? static_cast<int>(tri_h) + 1 : 0);
  label_font_.draw(base_, bar.x0, top_outer - static_cast<int>(std::lround(0.5 * px)), field_.unit, text_darkness);
}

IndexedImage FrameRenderer::draw(const FrameData& frame) const {
  IndexedImage image = base_;
  const Layout& L = layout_;
  // A particle stands for an area dx^2 of water (or wall): its disc has that area. When particles
  // are only a few pixels apart, pixel rounding opens gaps between such discs that read as a moire
  // of white lines; there the radius grows smoothly (spacing 8 px down to 4 px) to 0.71 spacing,
  // which covers a square lattice.
  const double spacing = frame.dx * L.scale;
  double radius = spacing / std::sqrt(std::numbers::pi);
  radius += std::clamp((8.0 - spacing) / 4.0, 0.0, 1.0) * (0.71 * spacing - radius);
  const std::uint8_t wall = Palette::grey(wall_grey);
  const double span = range_.hi - range_.lo;
  // Walls first, then the fluid over them.
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < frame.size(); ++i) {
      const bool is_wall = frame.kind[i] != 0;
      if (is_wall != (pass == 0)) continue;
      const auto p = L.to_pixel(frame.x[i], frame.y[i]);
      std::uint8_t index = wall;
      if (!is_wall) {
        const float v = frame.value[i];
        index = std::isfinite(v) ? Palette::map_index((v - range_.lo) / span) : Palette::black;
      }
      fill_disc(image, p[0], p[1], radius, index, L.plot);
    }
  const std::string stamp = fmt::format("t = {:.{}f} s", frame.time, style_.time_decimals);
  title_font_.draw(image, L.plot.x1 - title_font_.text_width(stamp), title_baseline(), stamp, text_darkness);
  return image;
}

// ---------------------------------------------------------------------------------------------
// A run's frames

std::vector<std::pair<std::int64_t, fs::path>> list_frames(const fs::path& run_dir) {
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec))
    throw RenderError(fmt::format("{}: no such directory (give a run's output directory, e.g. out/dam_break)",
                                  run_dir.string()));
  const fs::path dir = run_dir / "frames";
  std::map<std::int64_t, fs::path> frames;
  bool vtu = false;
  static const std::regex pattern(R"(frame_(\d{1,18})\.npz)");
  if (fs::is_directory(dir, ec))
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      std::smatch m;
      if (std::regex_match(name, m, pattern)) frames[std::stoll(m[1].str())] = entry.path();
      else if (entry.path().extension() == ".vtu") vtu = true;
    }
  if (frames.empty())
    throw RenderError(vtu ? fmt::format("{}: no .npz frames, only .vtu (render reads the .npz frames: run the case "
                                        "with output.formats including \"npz\")",
                                        dir.string())
                          : fmt::format("{}: no frames (frames/frame_NNNNNN.npz); is it a run's output directory?",
                                        run_dir.string()));
  std::vector<std::pair<std::int64_t, fs::path>> out(frames.begin(), frames.end());
  for (std::size_t k = 1; k < out.size(); ++k)
    if (out[k].first != out[k - 1].first + 1)
      throw FormatError(fmt::format("{}: frame {} is missing (frames {} to {} are there, with gaps)", dir.string(),
                                    out[k - 1].first + 1, out.front().first, out.back().first));
  return out;
}

namespace {

struct FrameSummary {
  double time = 0.0, dx = 0.0;
  Box box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  double vmin = std::numeric_limits<double>::infinity(), vmax = -std::numeric_limits<double>::infinity();
  std::vector<float> samples;
};

FrameData load(const fs::path& path, Field field) {
  FrameData d = extract(read_npz_frame(path), field);
  if (!(d.dx > 0.0) || !std::isfinite(d.dx))
    throw FormatError(fmt::format("{}: not a sluice frame: dx = {} is not a positive spacing", path.string(), d.dx));
  return d;
}

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

}  // namespace

RenderResult render_run(const fs::path& run_dir, const RenderOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const FieldInfo& info = field_info(o.field);
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

  const auto files = list_frames(run_dir);
  const std::size_t n = files.size();

  // Pass 1: read every frame (so that a damaged one stops us before anything is written), for the
  // domain to show and the colour range.
  std::vector<FrameSummary> summaries(n);
  std::vector<std::exception_ptr> errors(n);
  const std::size_t max_samples = std::max<std::size_t>(1000, 4'000'000 / n);
#pragma omp parallel for schedule(dynamic)
  for (std::size_t i = 0; i < n; ++i) {
    try {
      summaries[i] = summarise(load(files[i].second, o.field), max_samples);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);

  Range range;
  if (o.range) range = *o.range;
  else {
    std::vector<float> samples;
    for (auto& s : summaries) samples.insert(samples.end(), s.samples.begin(), s.samples.end());
    range = data_range(info, std::move(samples));
  }
  double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;
  for (const auto& s : summaries) {
    vmin = std::min(vmin, s.vmin);
    vmax = std::max(vmax, s.vmax);
  }
  const double tolerance = 1e-6 * (range.hi - range.lo);

  // The domain: the first frame's extent (walls and all), grown to take in particles that leave it
  // later, but by no more than a quarter of its size each way (a particle flung far away must not
  // shrink the picture), plus the particles' radius.
  Box box = summaries.front().box;
  if (!(box.x1 >= box.x0 && box.y1 >= box.y0))
    throw FormatError(fmt::format("{}: no particle has a finite position", files.front().second.string()));
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
  box = {box.x0 - pad, box.y0 - pad, box.x1 + pad, box.y1 + pad};

  // The frames to draw.
  std::vector<std::size_t> chosen;
  if (o.times.empty()) {
    for (std::size_t i = 0; i < n; ++i) chosen.push_back(i);
  } else {
    std::vector<double> gaps;
    for (std::size_t i = 1; i < n; ++i) gaps.push_back(summaries[i].time - summaries[i - 1].time);
    double interval = 0.0;
    if (!gaps.empty()) {
      std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
      interval = gaps[gaps.size() / 2];
    }
    for (const double t : o.times) {
      std::size_t best = 0;
      for (std::size_t i = 1; i < n; ++i)
        if (std::abs(summaries[i].time - t) < std::abs(summaries[best].time - t)) best = i;
      if (std::abs(summaries[best].time - t) > 0.5 * interval + 1e-9 * std::max(1.0, std::abs(t)))
        throw RenderError(fmt::format("--times {}: no frame at t = {} s (the frames run from t = {} to {} s{})", t, t,
                                      summaries.front().time, summaries.back().time,
                                      interval > 0 ? fmt::format(", every {:.6g} s", interval) : ""));
      if (std::find(chosen.begin(), chosen.end(), best) == chosen.end()) chosen.push_back(best);
    }
  }

  double interval = n > 1 ? (summaries.back().time - summaries.front().time) / static_cast<double>(n - 1) : 0.1;
  Style style;
  const std::string case_name = case_name_of(run_dir);
  style.title = case_name.empty() ? std::string(info.title) : fmt::format("{} \u2014 {}", case_name, info.title);
  style.extend_low = vmin < range.lo - tolerance;
  style.extend_high = vmax > range.hi + tolerance;
  style.time_decimals = decimals_for(interval);
  const FrameRenderer renderer(info, range, box, o.width, o.height, style);
  const Layout& L = renderer.layout();

  RenderResult result;
  result.width = L.width;
  result.height = L.height;
  result.range = range;
  result.range_from_data = !o.range.has_value();
  result.field_title = info.title;
  result.unit = info.unit;
  result.frames = static_cast<int>(chosen.size());

  // Pass 2: draw in parallel, encode in order.
  const std::string stem(info.name);
  if (o.format == Format::png) {
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
    std::vector<fs::path> paths(chosen.size());
    for (std::size_t k = 0; k < chosen.size(); ++k)
      paths[k] = single ? *single : dir / fmt::format("{}_{:06}.png", stem, files[chosen[k]].first);
    parallel_in_order(
        chosen.size(),
        [&](std::size_t k) {
          const FrameData d = load(files[chosen[k]].second, o.field);
          write_png(paths[k], renderer.draw(d), renderer.palette());
          return 0;
        },
        [](std::size_t, int) {});
    result.files = paths;
    result.fps = 0.0;
  } else {
    const fs::path path =
        o.output.empty() ? run_dir / (stem + std::string(format_extension(o.format))) : o.output;
    if (path.has_parent_path()) create_directories_or_throw(path.parent_path());
    std::unique_ptr<AnimationWriter> writer;
    if (o.format == Format::gif) {
      const int delay = static_cast<int>(std::lround(100.0 / o.fps));
      writer = open_gif(path, L.width, L.height, renderer.palette(), delay);
      result.fps = 100.0 / delay;
    } else {
      writer = open_mp4(path, L.width, L.height, renderer.palette(), o.fps);
      result.fps = o.fps;
    }
    parallel_in_order(
        chosen.size(), [&](std::size_t k) { return renderer.draw(load(files[chosen[k]].second, o.field)); },
        [&](std::size_t, const IndexedImage& image) { writer->add(image); });
    writer->finish();
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
