// Pictures are drawn in palette indices, one byte per pixel. The 256-entry palette holds the colour
// map's levels, a grey ramp (background, walls, text) and one entry never drawn (GIF frames mark
// unchanged pixels with it as transparent), so GIF and palette PNG encode a picture exactly, and MP4
// gets it expanded to RGB.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "sluice/render/colormap.hpp"

namespace sluice::render {

struct Palette {
  static constexpr int map_levels = 224;   // indices 0 .. 223: the colour map, low to high
  static constexpr int grey_levels = 31;   // indices 224 .. 254: white (224) to black (254)
  static constexpr std::uint8_t transparent = 255;  // never drawn
  static_assert(map_levels + grey_levels + 1 == 256);

  std::array<Rgb, 256> colours{};

  // Level k of the map is the map's colour at k / (map_levels - 1): the ends are the map's ends.
  static Palette for_map(Colormap map);

  // The level for t in [0, 1] (clamped; NaN gives level 0), rounded to the nearest level.
  static std::uint8_t map_index(double t);
  // Grey `level` from 0 (white) to grey_levels - 1 (black).
  static std::uint8_t grey(int level);
  static constexpr std::uint8_t white = map_levels;

  // Pictures of 3D runs shade the map instead: shade_levels brightnesses (from darkest_shade times the
  // map's colour up to the map's colour) of shaded_levels levels of the map.
  static constexpr int shade_levels = 4;
  static constexpr int shaded_levels = map_levels / shade_levels;
  static constexpr double darkest_shade = 0.45;
  static_assert(shade_levels * shaded_levels == map_levels);
  static Palette for_map_shaded(Colormap map);
  // The index of t in [0, 1] (clamped; NaN gives the low end) at `shade` (0 darkest .. shade_levels - 1,
  // the map's own colour) in a shaded palette.
  static std::uint8_t shaded_index(double t, int shade);
  static constexpr std::uint8_t black = map_levels + grey_levels - 1;
};

struct Rect {  // pixels x0 <= x < x1, y0 <= y < y1
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  [[nodiscard]] int width() const { return x1 - x0; }
  [[nodiscard]] int height() const { return y1 - y0; }
};

struct IndexedImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // row-major, row 0 at the top

  IndexedImage() = default;
  IndexedImage(int w, int h, std::uint8_t fill) : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}
  [[nodiscard]] std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  std::uint8_t& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  [[nodiscard]] Rect bounds() const { return {0, 0, width, height}; }
};

void fill_rect(IndexedImage& image, Rect r, std::uint8_t index);

// Fills the pixels whose centres lie within `radius` of (cx, cy) (pixel units, the centre of pixel
// (i, j) being (i + 0.5, j + 0.5)), and always the pixel containing (cx, cy), so that a particle
// smaller than a pixel still shows. Only pixels inside `clip` are touched.
void fill_disc(IndexedImage& image, double cx, double cy, double radius, std::uint8_t index, Rect clip);

// A disc drawn as a sphere lit from the upper left front: each pixel takes ramp[k] (the ramp runs from
// dark to light), k from the Lambert brightness of the sphere's surface there (a quarter of it
// ambient) times `dim` (0 to 1). Pixels as fill_disc.
void fill_sphere(IndexedImage& image, double cx, double cy, double radius, double dim,
                 std::span<const std::uint8_t> ramp, Rect clip);

// A filled triangle (vertices in pixel units), pixel centres inside it.
void fill_triangle(IndexedImage& image, std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c,
                   std::uint8_t index);

// RGB triples, row-major.
std::vector<std::uint8_t> to_rgb(const IndexedImage& image, const Palette& palette);

}  // namespace sluice::render
