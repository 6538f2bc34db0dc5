#include "sluice/render/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace sluice::render {

namespace {

Rgb interpolate(std::span<const std::array<float, 3>> knots, double t) {
  if (!(t > 0.0)) t = 0.0;  // also NaN
  if (t > 1.0) t = 1.0;
  const double pos = t * static_cast<double>(knots.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(pos), knots.size() - 2);
  const double f = pos - static_cast<double>(k);
  auto channel = [&](int c) {
    const double v = (1.0 - f) * knots[k][c] + f * knots[k + 1][c];
    return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255.0));
  };
  return {channel(0), channel(1), channel(2)};
}

}  // namespace

Rgb colormap_at(Colormap map, double t) {
  switch (map) {
    case Colormap::viridis: return interpolate(tables::viridis, t);
    case Colormap::coolwarm: return interpolate(tables::coolwarm, t);
  }
  return {};
}

}  // namespace sluice::render
