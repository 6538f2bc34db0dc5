#include "sluice/render/camera.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <numbers>

#include "sluice/render/render_error.hpp"

namespace sluice::render {

namespace {

struct NamedView {
  std::string_view name;
  Camera camera;
};

// front: the camera on -y looking along +y (x right); side: on +x looking along -x (y right); top:
// above, looking down z (x right, y up, as its azimuth puts the camera's right on +x).
constexpr std::array<NamedView, 4> views = {{
    {"iso", {-60.0, 30.0}},
    {"front", {-90.0, 0.0}},
    {"side", {0.0, 0.0}},
    {"top", {-90.0, 90.0}},
}};

double parse_degrees(std::string_view flag, std::string_view text) {
  double v = 0.0;
  std::string_view s = text;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
    throw RenderError(fmt::format("{} '{}': expected an angle in degrees, e.g. 30", flag, text));
  return v;
}

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

}  // namespace

Camera named_view(std::string_view name) {
  for (const auto& v : views)
    if (v.name == name) return v.camera;
  throw RenderError(fmt::format("--view '{}': unknown view; the views are iso, front, side, top", name));
}

std::string_view default_view_name() { return views.front().name; }

double parse_azimuth(std::string_view text) { return parse_degrees("--azimuth", text); }

double parse_elevation(std::string_view text) {
  const double e = parse_degrees("--elevation", text);
  if (e < -90.0 || e > 90.0)
    throw RenderError(fmt::format("--elevation {}: give -90 to 90 degrees (90 looks straight down)", text));
  return e;
}

Projection::Projection(Camera camera) {
  const double a = radians(camera.azimuth), e = radians(camera.elevation);
  toward_ = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  right_ = {-std::sin(a), std::cos(a), 0.0};
  // up = toward x right: vertical for a level camera, the far side of the scene seen from above.
  up_ = {toward_[1] * right_[2] - toward_[2] * right_[1], toward_[2] * right_[0] - toward_[0] * right_[2],
         toward_[0] * right_[1] - toward_[1] * right_[0]};
}

Projected Projection::operator()(const Vec3& p) const {
  auto dot = [&p](const Vec3& d) { return p[0] * d[0] + p[1] * d[1] + p[2] * d[2]; };
  return {dot(right_), dot(up_), dot(toward_)};
}

std::string describe(Camera camera) {
  for (const auto& v : views)
    if (v.camera.azimuth == camera.azimuth && v.camera.elevation == camera.elevation)
      return fmt::format("{} view", v.name);
  return fmt::format("azimuth {:g}\u00B0, elevation {:g}\u00B0", camera.azimuth, camera.elevation);
}

}  // namespace sluice::render
