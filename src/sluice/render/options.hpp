// What sluice render is asked to draw: the field, the file format, the size, the colour range, the
// frames; and the parsers of the command line's text for them.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sluice/render/color_range.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/scene3d.hpp"

namespace sluice::render {

enum class Format { gif, mp4, png };

// Each throws RenderError with a message naming the option for text it cannot take.
Format parse_format(std::string_view text);
Range parse_range(std::string_view text);                // "MIN:MAX", MIN < MAX
std::pair<int, int> parse_size(std::string_view text);   // "WxH"
std::vector<double> parse_times(std::string_view text);  // "t1,t2,..."

std::string_view format_extension(Format format);  // ".gif", ".mp4", ".png"

struct RenderOptions {
  Field field = Field::speed;
  Format format = Format::gif;
  std::filesystem::path output;  // file (gif, mp4; png with one picture) or directory (png); empty: default
  int fps = 20;
  int width = 0, height = 0;     // 0: default size
  std::optional<Range> range;    // shown units; empty: from the data
  std::vector<double> times;     // png only: the frames nearest these times; empty: every frame
  // 3D runs only: the camera (default: the iso view) or a slice. camera_flag names the flag that
  // chose the camera (--view, --azimuth or --elevation), for the error on a 2D run.
  std::optional<Camera> camera;
  std::string camera_flag;
  std::optional<Slice> slice;
};

}  // namespace sluice::render
