#include "sluice/render/frame_renderer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string_view>
#include <utility>

#include "sluice/render/render_error.hpp"
#include "sluice/render/ticks.hpp"

namespace sluice::render {

namespace {

constexpr int text_darkness = Palette::grey_levels - 1;
constexpr int frame_darkness = 22;  // colour-bar outline and ticks

int title_px_for(int width, int height) {
  if (width <= 0 || height <= 0) return 16;
  return std::clamp(static_cast<int>(std::lround(std::min(width / 62.0, height / 30.0))), 10, 40);
}
int label_px_for(int title_px) { return std::max(9, static_cast<int>(std::lround(0.85 * title_px))); }

// Distances in pixels that scale with the title font's pixel size.
struct Spacing {
  int margin, top, bar_w, gap, tick_len, label_gap;
};

Spacing spacing_for(int px) {
  return {.margin = std::max(6, static_cast<int>(std::lround(0.75 * px))),
          .top = static_cast<int>(std::lround(2.3 * px)),
          .bar_w = std::max(10, static_cast<int>(std::lround(1.1 * px))),
          .gap = px,
          .tick_len = std::max(3, static_cast<int>(std::lround(0.35 * px))),
          .label_gap = std::max(3, static_cast<int>(std::lround(0.3 * px)))};
}

// The height of a pointed end of the colour bar.
int end_height(int bar_w) { return static_cast<int>(std::lround(0.9 * bar_w)); }

// The room the labels beside the colour bar need: the widest tick label for any number of ticks the
// bar may get, or the unit written above the bar where it reaches further.
int label_width(const Font& label_font, Range range, std::string_view unit, const Spacing& sp) {
  int width = 0;
  for (int n = 2; n <= 10; ++n) {
    const auto ticks = nice_ticks(range, n);
    const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
    for (double t : ticks) width = std::max(width, label_font.text_width(tick_label(t, step)));
  }
  return std::max(width, label_font.text_width(unit) - sp.bar_w - sp.tick_len - sp.label_gap);
}

// The picture's size, the room in it for the domain and the pixels per metre.
struct Area {
  int width = 0, height = 0;  // the picture
  int room_w = 0, room_h = 0;  // for the domain
  double scale = 0.0;
};

Area fit_area(double world_w, double world_h, int width, int height, const Spacing& sp, int panel_w, int min_bar) {
  Area a;
  if (width <= 0 || height <= 0) {  // default: about 900 x 600 pixels for the domain
    a.scale = std::min(900.0 / world_w, 600.0 / world_h);
    a.room_w = std::max(1, static_cast<int>(std::lround(world_w * a.scale)));
    a.room_h = std::max(static_cast<int>(std::lround(world_h * a.scale)), min_bar);
    a.width = sp.margin + a.room_w + panel_w;
    a.height = sp.top + a.room_h + sp.margin;
    a.width += a.width % 2;  // even sizes suit video encoders
    a.height += a.height % 2;
    return a;
  }
  a.width = width;
  a.height = height;
  a.room_w = width - sp.margin - panel_w;
  a.room_h = height - sp.top - sp.margin;
  if (a.room_w < 40 || a.room_h < 40)
    throw RenderError(fmt::format("--size {}x{}: too small for the picture, its colour bar and labels", width, height));
  a.scale = std::min(a.room_w / world_w, a.room_h / world_h);
  return a;
}

// The plot centred in its room, showing the world box centred on the requested one.
void place_plot(Layout& L, const Box& world, const Area& a, const Spacing& sp) {
  const double s = a.scale;
  const int plot_w = std::clamp(static_cast<int>(std::lround((world.x1 - world.x0) * s)), 1, a.room_w);
  const int plot_h = std::clamp(static_cast<int>(std::lround((world.y1 - world.y0) * s)), 1, a.room_h);
  L.plot.x0 = sp.margin + (a.room_w - plot_w) / 2;
  L.plot.y0 = sp.top + (a.room_h - plot_h) / 2;
  L.plot.x1 = L.plot.x0 + plot_w;
  L.plot.y1 = L.plot.y0 + plot_h;
  L.scale = s;
  const double cx = 0.5 * (world.x0 + world.x1), cy = 0.5 * (world.y0 + world.y1);
  L.world = {cx - 0.5 * plot_w / s, cy - 0.5 * plot_h / s, cx + 0.5 * plot_w / s, cy + 0.5 * plot_h / s};
}

// The colour bar right of the plot, as high as it (at least min_bar), shortened by its pointed ends.
void place_bar(Layout& L, const Area& a, const Spacing& sp, int min_bar, const Style& style) {
  const int bar_h = std::max(L.plot.height(), std::min(a.room_h, min_bar));
  L.bar.x0 = L.plot.x1 + sp.gap;
  L.bar.x1 = L.bar.x0 + sp.bar_w;
  L.bar.y0 = std::clamp((L.plot.y0 + L.plot.y1) / 2 - bar_h / 2, sp.top, sp.top + a.room_h - bar_h);
  L.bar.y1 = L.bar.y0 + bar_h;
  const int tri_h = end_height(sp.bar_w);
  if (style.extend_high) L.bar.y0 += tri_h + 1;
  if (style.extend_low) L.bar.y1 -= tri_h + 1;
  if (L.bar.height() < 8)
    throw RenderError(fmt::format("--size {}x{}: too small for the colour bar", L.width, L.height));
}

Layout make_layout(const FieldInfo& field, Range range, const Box& world, int width, int height, const Style& style,
                   const Font& title_font, const Font& label_font) {
  if (!(range.lo < range.hi)) throw RenderError("the colour range is empty");
  const double world_w = world.x1 - world.x0, world_h = world.y1 - world.y0;
  if (!(world_w > 0 && world_h > 0 && std::isfinite(world_w) && std::isfinite(world_h)))
    throw RenderError("the domain to draw is empty");
  Layout L;
  L.font_px = title_font.pixel_size();
  const Spacing sp = spacing_for(L.font_px);
  const int panel_w = sp.gap + sp.bar_w + sp.tick_len + sp.label_gap + label_width(label_font, range, field.unit, sp) +
                      sp.margin;
  const int min_bar = 12 * label_font.pixel_size();
  const Area a = fit_area(world_w, world_h, width, height, sp, panel_w, min_bar);
  L.width = a.width;
  L.height = a.height;
  place_plot(L, world, a, sp);
  place_bar(L, a, sp, min_bar, style);
  return L;
}

// A particle stands for an area dx^2 of water (or wall): its disc has that area. When particles are
// only a few pixels apart, pixel rounding opens gaps between such discs that read as a moire of
// white lines; there the radius grows smoothly (spacing 8 px down to 4 px) to 0.71 spacing, which
// covers a square lattice.
double disc_radius(double spacing) {
  const double radius = spacing / std::sqrt(std::numbers::pi);
  return radius + std::clamp((8.0 - spacing) / 4.0, 0.0, 1.0) * (0.71 * spacing - radius);
}

}  // namespace

FrameRenderer::FrameRenderer(const FieldInfo& field, Range range, Box world, int width, int height, Style style,
                             const std::filesystem::path& font_file)
    : field_(field), range_(range), style_(std::move(style)), palette_(style_.shaded ? Palette::for_map_shaded(field.map) : Palette::for_map(field.map)),
      title_font_(font_file, title_px_for(width, height)),
      label_font_(font_file, label_px_for(title_px_for(width, height))),
      layout_(make_layout(field, range, world, width, height, style_, title_font_, label_font_)) {
  draw_static();
}

int FrameRenderer::title_baseline() const {
  // Just above the plot, which is centred in the room a given --size leaves.
  const int px = layout_.font_px;
  return std::max(static_cast<int>(std::lround(1.5 * px)), layout_.plot.y0 - static_cast<int>(std::lround(0.8 * px)));
}

void FrameRenderer::draw_static() {
  base_ = IndexedImage(layout_.width, layout_.height, Palette::white);
  draw_title();
  draw_colour_bar();
  draw_ticks();
  draw_unit();
}

// The case's title, or the short title, or the field's if those do not fit beside the time stamp, or none.
void FrameRenderer::draw_title() {
  const int time_w = title_font_.text_width(fmt::format("t = {:.{}f} s", 8888.0, style_.time_decimals));
  const int room = layout_.plot.width() - time_w - layout_.font_px;
  for (const std::string& title : {style_.title, style_.short_title, std::string(field_.title)})
    if (!title.empty() && title_font_.text_width(title) <= room) {
      title_font_.draw(base_, layout_.plot.x0, title_baseline(), title, text_darkness);
      return;
    }
}

// Low values at the bottom, with a one-pixel outline and the pointed ends.
void FrameRenderer::draw_colour_bar() {
  const Rect& bar = layout_.bar;
  const int bar_h = bar.height();
  fill_rect(base_, {bar.x0 - 1, bar.y0 - 1, bar.x1 + 1, bar.y1 + 1}, Palette::grey(frame_darkness));
  for (int y = bar.y0; y < bar.y1; ++y) {
    const double t = bar_h > 1 ? static_cast<double>(bar.y1 - 1 - y) / (bar_h - 1) : 0.5;
    fill_rect(base_, {bar.x0, y, bar.x1, y + 1}, bar_index(t));
  }
  const int tri_h = end_height(bar.width());
  const double mid = 0.5 * (bar.x0 + bar.x1);
  if (style_.extend_high)
    fill_triangle(base_, {double(bar.x0), double(bar.y0)}, {double(bar.x1), double(bar.y0)},
                  {mid, double(bar.y0 - 1 - tri_h)}, bar_index(1.0));
  if (style_.extend_low)
    fill_triangle(base_, {double(bar.x0), double(bar.y1)}, {double(bar.x1), double(bar.y1)},
                  {mid, double(bar.y1 + 1 + tri_h)}, bar_index(0.0));
}

void FrameRenderer::draw_ticks() {
  const Rect& bar = layout_.bar;
  const int bar_h = bar.height();
  const Spacing sp = spacing_for(layout_.font_px);
  const int tick_w = layout_.font_px >= 24 ? 2 : 1;
  const int max_ticks = std::clamp(static_cast<int>(bar_h / (4.0 * label_font_.pixel_size())), 2, 8);
  const auto ticks = nice_ticks(range_, max_ticks);
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
  for (const double v : ticks) {
    const double f = (v - range_.lo) / (range_.hi - range_.lo);
    const int y = bar.y1 - 1 - static_cast<int>(std::lround(f * (bar_h - 1)));
    fill_rect(base_, {bar.x1, y - tick_w / 2, bar.x1 + sp.tick_len, y - tick_w / 2 + tick_w},
              Palette::grey(frame_darkness));
    label_font_.draw(base_, bar.x1 + sp.tick_len + sp.label_gap, y + label_font_.digit_height() / 2,
                     tick_label(v, step), text_darkness);
  }
}

// The unit above the colour bar (and its pointed end).
void FrameRenderer::draw_unit() {
  const Rect& bar = layout_.bar;
  const int top_outer = bar.y0 - (style_.extend_high ? end_height(bar.width()) + 1 : 0);
  label_font_.draw(base_, bar.x0, top_outer - static_cast<int>(std::lround(0.5 * layout_.font_px)), field_.unit,
                   text_darkness);
}

std::uint8_t FrameRenderer::bar_index(double t) const {
  return style_.shaded ? Palette::shaded_index(t, Palette::shade_levels - 1) : Palette::map_index(t);
}

// Walls first, then the fluid over them.
void FrameRenderer::draw_flat(IndexedImage& image, const FrameData& frame) const {
  const Layout& L = layout_;
  const double radius = disc_radius(frame.dx * L.scale);
  const std::uint8_t wall = Palette::grey(wall_grey), body = Palette::grey(body_grey);
  const double span = range_.hi - range_.lo;
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < frame.size(); ++i) {
      const bool is_wall = frame.kind[i] != 0;
      if (is_wall != (pass == 0)) continue;
      const auto p = L.to_pixel(frame.x[i], frame.y[i]);
      std::uint8_t index = frame.kind[i] == 2 ? body : wall;
      if (!is_wall) {
        const float v = frame.value[i];
        index = std::isfinite(v) ? Palette::map_index((v - range_.lo) / span) : Palette::black;
      }
      fill_disc(image, p[0], p[1], radius, index, L.plot);
    }
}

// In the frame's order (far to near), each particle a lit sphere, dimmer the farther it is.
void FrameRenderer::draw_spheres(IndexedImage& image, const FrameData& frame) const {
  const Layout& L = layout_;
  const double radius = disc_radius(frame.dx * L.scale);
  const double span = range_.hi - range_.lo;
  std::array<std::uint8_t, Palette::shade_levels> walls{}, bodies{}, ramp{};
  for (int s = 0; s < Palette::shade_levels; ++s) {
    walls[s] = Palette::grey(wall_ramp[s]);
    bodies[s] = Palette::grey(body_ramp[s]);
  }
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const auto p = L.to_pixel(frame.x[i], frame.y[i]);
    const double dim = far_dim + (1.0 - far_dim) * frame.depth[i];
    if (frame.kind[i] != 0) {
      fill_sphere(image, p[0], p[1], radius, dim, frame.kind[i] == 2 ? bodies : walls, L.plot);
      continue;
    }
    const float v = frame.value[i];
    for (int s = 0; s < Palette::shade_levels; ++s)
      ramp[s] = std::isfinite(v) ? Palette::shaded_index((v - range_.lo) / span, s) : Palette::black;
    fill_sphere(image, p[0], p[1], radius, dim, ramp, L.plot);
  }
}

IndexedImage FrameRenderer::draw(const FrameData& frame) const {
  IndexedImage image = base_;
  const Layout& L = layout_;
  if (frame.depth.empty()) draw_flat(image, frame);
  else draw_spheres(image, frame);
  const std::string stamp = fmt::format("t = {:.{}f} s", frame.time, style_.time_decimals);
  title_font_.draw(image, L.plot.x1 - title_font_.text_width(stamp), title_baseline(), stamp, text_darkness);
  return image;
}

}  // namespace sluice::render
