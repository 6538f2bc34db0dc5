// One frame as a picture: each particle a filled disc of its physical size (the area dx^2 it stands
// for: radius dx/sqrt(pi); a little larger when particles are under 8 pixels apart, see
// FrameRenderer::draw), walls in grey, fluid coloured by a field on a fixed colour range, with a
// colour bar and the simulated time. A 3D frame seen by a camera (depth given) is drawn far to near as
// spheres in a shaded palette: lit from the upper left, darker with depth, walls in faint grey.
#pragma once

#include <array>
#include <filesystem>
#include <string>

#include "sluice/render/color_range.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/font.hpp"
#include "sluice/render/image.hpp"

namespace sluice::render {

struct Box {
  double x0 = 0.0, y0 = 0.0, x1 = 1.0, y1 = 1.0;
};

// Where things go in the picture.
struct Layout {
  int width = 0, height = 0;
  int font_px = 16;
  Rect plot;         // the domain's pixels
  Box world;         // the domain shown (metres): plot.x0 is world.x0, plot.y1 is world.y0
  double scale = 1;  // pixels per metre, the same in x and y
  Rect bar;          // the colour bar (without its pointed ends)
  // Continuous pixel coordinates of a point in metres (y up in the world, down in the picture).
  [[nodiscard]] std::array<double, 2> to_pixel(double x, double y) const {
    return {plot.x0 + (x - world.x0) * scale, plot.y1 - (y - world.y0) * scale};
  }
};

struct Style {
  std::string title;              // drawn at the top left
  bool extend_low = false;        // some values lie below the range: pointed lower end
  bool extend_high = false;       // ... above it
  int time_decimals = 2;
  bool shaded = false;            // 3D frames seen by a camera: the shaded palette
  std::string short_title;        // drawn instead where the title does not fit (then the field's title)
};

// Draws frames of one field with a fixed range, layout and fonts. Thread-safe: draw() is const.
class FrameRenderer {
 public:
  // width/height 0: a default size fitted to the domain's aspect ratio.
  FrameRenderer(const FieldInfo& field, Range range, Box world, int width, int height, Style style,
                const std::filesystem::path& font_file = default_font_file());

  [[nodiscard]] const Layout& layout() const { return layout_; }
  [[nodiscard]] const Palette& palette() const { return palette_; }
  [[nodiscard]] IndexedImage draw(const FrameData& frame) const;

  static constexpr int wall_grey = 13;  // grey level of walls (0 white .. 30 black): RGB 145
  // Grey levels of walls seen by a camera, dark to light (RGB 179 to 230): faint behind the water.
  static constexpr std::array<int, Palette::shade_levels> wall_ramp = {9, 7, 5, 3};
  // The case's [[wall]] bodies (a gate, a paddle, a floating body), darker than the tank's walls.
  static constexpr int body_grey = 20;
  static constexpr std::array<int, Palette::shade_levels> body_ramp = {17, 15, 13, 11};
  // The brightness factor of the farthest particles seen by a camera (the nearest: 1).
  static constexpr double far_dim = 0.6;

 private:
  // What every frame shares, drawn once into base_.
  void draw_static();
  void draw_title();
  void draw_colour_bar();
  void draw_ticks();
  void draw_unit();
  [[nodiscard]] int title_baseline() const;
  [[nodiscard]] std::uint8_t bar_index(double t) const;  // the colour bar's colour for t in [0, 1]
  void draw_flat(IndexedImage& image, const FrameData& frame) const;
  void draw_spheres(IndexedImage& image, const FrameData& frame) const;

  FieldInfo field_;
  Range range_;
  Style style_;
  Palette palette_;
  Font title_font_, label_font_;
  Layout layout_;
  IndexedImage base_;
};

}  // namespace sluice::render
