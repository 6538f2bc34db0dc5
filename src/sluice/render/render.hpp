// Pictures and animations of a run, headless: reads the frames a run wrote
// (OUTPUT_DIR/frames/frame_NNNNNN.npz) and draws each particle as a filled disc of its physical size
// (the area dx^2 it stands for: radius dx/sqrt(pi); a little larger when particles are under 8 pixels
// apart, see FrameRenderer::draw), walls in grey, fluid coloured by a field on a fixed colour range, with a colour bar
// and the simulated time. Writes an animated GIF, an MP4 (through ffmpeg) or PNG snapshots.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sluice/io/frames.hpp"
#include "sluice/render/font.hpp"
#include "sluice/render/image.hpp"

namespace sluice::render {

// A request that cannot be met: unknown field, malformed option, no frames, a time with no frame.
// Damaged frames raise sluice::FormatError and unreadable files sluice::IoError instead.
struct RenderError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Field { vx, vy, speed, pressure, density };
enum class Format { gif, mp4, png };

struct FieldInfo {
  Field field;
  std::string_view name;   // as on the command line
  std::string_view title;  // as drawn
  std::string_view unit;   // the unit values are shown (and --range is given) in
  double scale;            // SI value * scale = shown value
  Colormap map;            // viridis for magnitudes, coolwarm for signed fields
  bool is_signed;          // the default range is symmetric about zero
};

const FieldInfo& field_info(Field field);
std::string field_names();  // "vx, vy, speed, pressure, density"

Field parse_field(std::string_view text);
Format parse_format(std::string_view text);
std::string_view format_extension(Format format);  // ".gif", ".mp4", ".png"

struct Range {
  double lo = 0.0, hi = 1.0;
};
Range parse_range(std::string_view text);                   // "MIN:MAX", MIN < MAX
std::pair<int, int> parse_size(std::string_view text);      // "WxH"
std::vector<double> parse_times(std::string_view text);     // "t1,t2,..."

// "Nice" tick values (steps of 1, 2, 2.5 or 5 times a power of ten) inside [lo, hi], at most
// max_ticks of them (at least two when the range allows), and their labels.
std::vector<double> nice_ticks(Range range, int max_ticks);
std::string tick_label(double value, double step);

// A frame reduced to what is drawn: positions, the field's value in its shown unit, and kind.
struct FrameData {
  double time = 0.0;
  double dx = 0.0;
  std::vector<float> x, y, value;
  std::vector<std::uint8_t> kind;  // 0 fluid, 1 wall
  [[nodiscard]] std::size_t size() const { return x.size(); }
};
FrameData extract(const Frame& frame, Field field);

// The default colour range from sampled fluid values (shown units): from the 0.1 % to the 99.9 %
// quantile, so that one outlier does not wash out the picture (from 0 for speed; symmetric about 0
// for signed fields). Values outside the range are drawn in the end colours, and the colour bar
// then has a pointed end.
Range data_range(const FieldInfo& info, std::vector<float> samples);

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

 private:
  void draw_static();
  [[nodiscard]] int title_baseline() const;

  FieldInfo field_;
  Range range_;
  Style style_;
  Palette palette_;
  Font title_font_, label_font_;
  Layout layout_;
  IndexedImage base_;
};

// The frames of a run, in order: (frame number, path of OUTPUT_DIR/frames/frame_NNNNNN.npz).
// RenderError if there are none or the numbering has a gap (a missing frame).
std::vector<std::pair<std::int64_t, std::filesystem::path>> list_frames(const std::filesystem::path& run_dir);

struct RenderOptions {
  Field field = Field::speed;
  Format format = Format::gif;
  std::filesystem::path output;  // file (gif, mp4; png with one picture) or directory (png); empty: default
  int fps = 20;
  int width = 0, height = 0;     // 0: default size
  std::optional<Range> range;    // shown units; empty: from the data
  std::vector<double> times;     // png only: the frames nearest these times; empty: every frame
};

struct RenderResult {
  std::vector<std::filesystem::path> files;
  int frames = 0;
  int width = 0, height = 0;
  double fps = 0.0;  // as played (GIF delays are whole hundredths of a second)
  Range range;
  bool range_from_data = true;
  std::string field_title, unit;
  double seconds = 0.0;
};

RenderResult render_run(const std::filesystem::path& run_dir, const RenderOptions& options);

// One line (or a few for PNG snapshots) saying what was written.
std::string describe(const RenderResult& result);

}  // namespace sluice::render
