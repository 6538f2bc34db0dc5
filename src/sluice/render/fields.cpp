#include "sluice/render/fields.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sluice/render/render_error.hpp"

namespace sluice::render {

namespace {

const std::array<FieldInfo, 6> fields = {{
    {Field::vx, "vx", "horizontal velocity vx", "velocity vx", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::vy, "vy", "vertical velocity vy", "velocity vy", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::vz, "vz", "vertical velocity vz", "vertical velocity vz", "m/s", 1.0, Colormap::coolwarm, true},
    {Field::speed, "speed", "speed |v|", "speed |v|", "m/s", 1.0, Colormap::viridis, false},
    {Field::pressure, "pressure", "pressure p", "pressure p", "kPa", 1e-3, Colormap::viridis, false},
    {Field::density, "density", "density \u03C1", "density \u03C1", "kg/m\u00B3", 1.0, Colormap::viridis, false},
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

FieldInfo field_info(Field field, int dimension) {
  FieldInfo info = field_info(field);
  if (dimension == 3) info.title = info.title_3d;
  return info;
}

namespace {

double value_of(Field field, const double* v, int dim, double pressure, double density) {
  switch (field) {
    case Field::vx: return v[0];
    case Field::vy: return v[1];
    case Field::vz: return v[2];
    case Field::speed: return std::sqrt(v[0] * v[0] + v[1] * v[1] + (dim == 3 ? v[2] * v[2] : 0.0));
    case Field::pressure: return pressure;
    case Field::density: return density;
  }
  return 0.0;
}

}  // namespace

FrameData extract(const Frame& frame, Field field) {
  const int dim = frame.dimension;
  if (dim != 2 && dim != 3) throw RenderError(fmt::format("the frame at t = {} s is {}D", frame.time, dim));
  if (field == Field::vz && dim == 2)
    throw RenderError("--field vz: the run is 2D (vz is the vertical velocity of 3D runs; in 2D it is vy)");
  const double scale = field_info(field).scale;
  const std::size_t n = frame.size();
  FrameData d;
  d.time = frame.time;
  d.dx = frame.dx;
  d.dimension = dim;
  d.x.resize(n);
  d.y.resize(n);
  if (dim == 3) d.z.resize(n);
  d.value.resize(n);
  d.kind = frame.kind();
  // The case's own walls (bodies from 2 on: a gate, a paddle, a floating body) are drawn apart from the
  // tank's.
  const bool bodies = std::any_of(frame.fields.begin(), frame.fields.end(),
                                  [](const FrameField& f) { return f.short_name == "body"; });
  if (bodies) {
    const auto& body = frame.body();
    for (std::size_t i = 0; i < n; ++i)
      if (d.kind[i] != 0 && body[i] >= 2) d.kind[i] = 2;
  }
  const auto& position = frame.position();
  const auto& velocity = frame.velocity();
  const auto& pressure = frame.pressure();
  const auto& density = frame.density();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = static_cast<std::size_t>(dim) * i;
    d.x[i] = static_cast<float>(position[k]);
    d.y[i] = static_cast<float>(position[k + 1]);
    if (dim == 3) d.z[i] = static_cast<float>(position[k + 2]);
    d.value[i] = static_cast<float>(value_of(field, &velocity[k], dim, pressure[i], density[i]) * scale);
  }
  return d;
}

}  // namespace sluice::render
