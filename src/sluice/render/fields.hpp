// What colours the water: the fields a picture can show (their names, units and colour maps), and a
// frame reduced to what is drawn of it.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "sluice/io/frames.hpp"
#include "sluice/render/colormap.hpp"

namespace sluice::render {

enum class Field { vx, vy, vz, speed, pressure, density };  // vz: 3D runs only

struct FieldInfo {
  Field field;
  std::string_view name;   // as on the command line
  std::string_view title;  // as drawn (2D)
  std::string_view title_3d;  // as drawn in 3D, where z is up and vy horizontal
  std::string_view unit;   // the unit values are shown (and --range is given) in
  double scale;            // SI value * scale = shown value
  Colormap map;            // viridis for magnitudes, coolwarm for signed fields
  bool is_signed;          // the default range is symmetric about zero
};

const FieldInfo& field_info(Field field);
// The field as drawn in `dimension` dimensions: its 3D title in 3D.
FieldInfo field_info(Field field, int dimension);

// RenderError naming the fields if `text` is none of them.
Field parse_field(std::string_view text);

// A frame reduced to what is drawn: positions, the field's value in its shown unit, and kind.
// A 3D frame has z too; a 3D frame seen by a camera (scene3d.hpp) has x, y in the picture's plane
// and depth (0 farthest .. 1 nearest), its particles ordered far to near.
struct FrameData {
  double time = 0.0;
  double dx = 0.0;
  int dimension = 2;
  std::vector<float> x, y, z, value;
  std::vector<float> depth;  // empty unless seen by a camera
  std::vector<std::uint8_t> kind;  // 0 fluid, 1 the tank's walls, 2 a [[wall]]'s (a body's)
  [[nodiscard]] std::size_t size() const { return x.size(); }
};

// RenderError for vz of a 2D frame.
FrameData extract(const Frame& frame, Field field);

}  // namespace sluice::render
