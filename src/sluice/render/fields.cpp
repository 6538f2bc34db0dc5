#include "sluice/render/fields.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sluice/render/render_error.hpp"

namespace sluice::render {

namespace {

const std::array<FieldInfo, 5> fields = {{
    {Field::vx, "vx", "horizontal velocity vx", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::vy, "vy", "vertical velocity vy", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::speed, "speed", "speed |v|", "m/s", 1.0, Colormap::viridis, false},
    {Field::pressure, "pressure", "pressure p", "kPa", 1e-3, Colormap::viridis, false},
    {Field::density, "density", "density \u03C1", "kg/m\u00B3", 1.0, Colormap::viridis, false},
}};

// "vx, vy, speed, pressure, density"
std::string field_names() {
  std::string s;
  for (const auto& f : fields) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

}  // namespace

const FieldInfo& field_info(Field field) {
  for (const auto& f : fields)
    if (f.field == field) return f;
  throw std::logic_error("field_info: unknown field");
}

Field parse_field(std::string_view text) {
  for (const auto& f : fields)
    if (f.name == text) return f.field;
  throw RenderError(fmt::format("unknown field '{}'; the fields are {}", text, field_names()));
}

FrameData extract(const Frame& frame, Field field) {
  if (frame.dimension != 2)
    throw RenderError(fmt::format("the frame at t = {} s is {}D; sluice render draws 2D runs (pictures of 3D runs "
                                  "are not implemented yet: open the .pvd in ParaView)",
                                  frame.time, frame.dimension));
  const double scale = field_info(field).scale;
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
    d.value[i] = static_cast<float>(v * scale);
  }
  return d;
}

}  // namespace sluice::render
