#include "sluice/render/image.hpp"

#include <algorithm>
#include <cmath>

namespace sluice::render {

Palette Palette::for_map(Colormap map) {
  Palette p;
  for (int k = 0; k < map_levels; ++k) p.colours[k] = colormap_at(map, static_cast<double>(k) / (map_levels - 1));
  for (int g = 0; g < grey_levels; ++g) {
    const auto v = static_cast<std::uint8_t>(std::lround(255.0 * (1.0 - static_cast<double>(g) / (grey_levels - 1))));
    p.colours[map_levels + g] = {v, v, v};
  }
  p.colours[transparent] = {255, 0, 255};
  return p;
}

std::uint8_t Palette::map_index(double t) {
  if (!(t > 0.0)) return 0;
  if (t >= 1.0) return map_levels - 1;
  return static_cast<std::uint8_t>(std::lround(t * (map_levels - 1)));
}

Palette Palette::for_map_shaded(Colormap map) {
  Palette p = for_map(map);
  for (int s = 0; s < shade_levels; ++s) {
    const double f = darkest_shade + (1.0 - darkest_shade) * s / (shade_levels - 1);
    for (int k = 0; k < shaded_levels; ++k) {
      const Rgb c = colormap_at(map, static_cast<double>(k) / (shaded_levels - 1));
      auto dim = [f](std::uint8_t v) { return static_cast<std::uint8_t>(std::lround(f * v)); };
      p.colours[s * shaded_levels + k] = {dim(c.r), dim(c.g), dim(c.b)};
    }
  }
  return p;
}

std::uint8_t Palette::shaded_index(double t, int shade) {
  const int level = !(t > 0.0) ? 0 : t >= 1.0 ? shaded_levels - 1 : static_cast<int>(std::lround(t * (shaded_levels - 1)));
  return static_cast<std::uint8_t>(std::clamp(shade, 0, shade_levels - 1) * shaded_levels + level);
}

std::uint8_t Palette::grey(int level) {
  return static_cast<std::uint8_t>(map_levels + std::clamp(level, 0, grey_levels - 1));
}

void fill_rect(IndexedImage& image, Rect r, std::uint8_t index) {
  const int x0 = std::max(r.x0, 0), x1 = std::min(r.x1, image.width);
  const int y0 = std::max(r.y0, 0), y1 = std::min(r.y1, image.height);
  if (x0 >= x1) return;
  for (int y = y0; y < y1; ++y)
    std::fill(image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * image.width + x0,
              image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * image.width + x1, index);
}

namespace {

// The pixel rows of a disc of `radius` centred at (cx, cy) inside `clip` (clamped to the image):
// span(y, xlo, xhi) for each row whose centre y + 0.5 is within the radius, with the pixels whose
// centres are inside the disc. Returns the clamped clip.
template <class Span>
Rect for_each_disc_row(const IndexedImage& image, double cx, double cy, double radius, Rect clip, Span&& span) {
  clip.x0 = std::max(clip.x0, 0);
  clip.y0 = std::max(clip.y0, 0);
  clip.x1 = std::min(clip.x1, image.width);
  clip.y1 = std::min(clip.y1, image.height);
  const double r2 = radius * radius;
  const int ylo = std::max(clip.y0, static_cast<int>(std::ceil(cy - radius - 0.5)));
  const int yhi = std::min(clip.y1 - 1, static_cast<int>(std::floor(cy + radius - 0.5)));
  for (int y = ylo; y <= yhi; ++y) {
    const double dy = y + 0.5 - cy;
    const double half = std::sqrt(std::max(0.0, r2 - dy * dy));
    const int xlo = std::max(clip.x0, static_cast<int>(std::ceil(cx - half - 0.5)));
    const int xhi = std::min(clip.x1 - 1, static_cast<int>(std::floor(cx + half - 0.5)));
    if (xlo <= xhi) span(y, xlo, xhi);
  }
  return clip;
}

}  // namespace

void fill_disc(IndexedImage& image, double cx, double cy, double radius, std::uint8_t index, Rect clip) {
  if (!std::isfinite(cx) || !std::isfinite(cy)) return;
  clip = for_each_disc_row(image, cx, cy, radius, clip, [&](int y, int xlo, int xhi) {
    std::fill(image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * image.width + xlo,
              image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * image.width + xhi + 1, index);
  });
  const double fx = std::floor(cx), fy = std::floor(cy);
  if (fx >= clip.x0 && fx < clip.x1 && fy >= clip.y0 && fy < clip.y1)
    image.at(static_cast<int>(fx), static_cast<int>(fy)) = index;
}

namespace {

// Lambert brightness of a unit sphere seen from the front at (nx, ny) (y up) from its centre, lit
// from the upper left front, a quarter of it ambient: 0.25 .. 1.
double sphere_brightness(double nx, double ny) {
  constexpr double lx = -0.40, ly = 0.45, lz = 0.80;  // |l| = 1.0
  const double nz = std::sqrt(std::max(0.0, 1.0 - nx * nx - ny * ny));
  return 0.25 + 0.75 * std::max(0.0, nx * lx + ny * ly + nz * lz);
}

}  // namespace

void fill_sphere(IndexedImage& image, double cx, double cy, double radius, double dim,
                 std::span<const std::uint8_t> ramp, Rect clip) {
  if (!std::isfinite(cx) || !std::isfinite(cy) || ramp.empty()) return;
  const double r = std::max(radius, 0.5);
  const int top = static_cast<int>(ramp.size()) - 1;
  auto index_at = [&](double dx, double dy) {
    const double b = dim * sphere_brightness(dx / r, -dy / r);
    return ramp[static_cast<std::size_t>(std::clamp(static_cast<int>(std::lround(b * top)), 0, top))];
  };
  clip = for_each_disc_row(image, cx, cy, radius, clip, [&](int y, int xlo, int xhi) {
    for (int x = xlo; x <= xhi; ++x) image.at(x, y) = index_at(x + 0.5 - cx, y + 0.5 - cy);
  });
  const double fx = std::floor(cx), fy = std::floor(cy);
  if (fx >= clip.x0 && fx < clip.x1 && fy >= clip.y0 && fy < clip.y1)
    image.at(static_cast<int>(fx), static_cast<int>(fy)) = index_at(fx + 0.5 - cx, fy + 0.5 - cy);
}

void fill_triangle(IndexedImage& image, std::array<double, 2> a, std::array<double, 2> b, std::array<double, 2> c,
                   std::uint8_t index) {
  auto edge = [](const std::array<double, 2>& p, const std::array<double, 2>& q, double x, double y) {
    return (q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]);
  };
  const double area = edge(a, b, c[0], c[1]);
  if (area == 0.0) return;
  const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}))));
  const int x1 = std::min(image.width - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}))));
  const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}))));
  const int y1 = std::min(image.height - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}))));
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5, py = y + 0.5;
      const double w0 = edge(b, c, px, py) / area, w1 = edge(c, a, px, py) / area, w2 = edge(a, b, px, py) / area;
      if (w0 >= 0 && w1 >= 0 && w2 >= 0) image.at(x, y) = index;
    }
}

std::vector<std::uint8_t> to_rgb(const IndexedImage& image, const Palette& palette) {
  std::vector<std::uint8_t> rgb(image.pixels.size() * 3);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const Rgb c = palette.colours[image.pixels[i]];
    rgb[3 * i] = c.r;
    rgb[3 * i + 1] = c.g;
    rgb[3 * i + 2] = c.b;
  }
  return rgb;
}

}  // namespace sluice::render
