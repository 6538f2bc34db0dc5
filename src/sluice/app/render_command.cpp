// sluice render: pictures and animations of a run's frames (see sluice/render/render.hpp).
#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "sluice/app/commands.hpp"
#include "sluice/render/camera.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/options.hpp"
#include "sluice/render/render.hpp"
#include "sluice/render/render_error.hpp"

namespace fs = std::filesystem;

namespace sluice::app {

namespace {

struct RenderArgs {
  std::string dir, field = "speed", format, output, size, range, times;
  std::string view, azimuth, elevation, slice, thickness;  // 3D runs
  int fps = 20;
  bool quiet = false;
};

// The camera of --view and/or --azimuth, --elevation (which override the view's angles), and the
// slice of --slice, --thickness.
void view_from(const RenderArgs& a, render::RenderOptions& o) {
  if (!a.view.empty() || !a.azimuth.empty() || !a.elevation.empty()) {
    render::Camera camera = render::named_view(a.view.empty() ? render::default_view_name() : a.view);
    if (!a.azimuth.empty()) camera.azimuth = render::parse_azimuth(a.azimuth);
    if (!a.elevation.empty()) camera.elevation = render::parse_elevation(a.elevation);
    o.camera = camera;
    o.camera_flag = !a.view.empty() ? "--view" : !a.azimuth.empty() ? "--azimuth" : "--elevation";
  }
  if (!a.thickness.empty() && a.slice.empty())
    throw render::RenderError("--thickness is the slab's thickness of --slice: give --slice AXIS=VALUE too");
  if (!a.slice.empty()) {
    o.slice = render::parse_slice(a.slice);
    if (!a.thickness.empty()) o.slice->thickness = render::parse_thickness(a.thickness);
  }
}

render::RenderOptions options_from(const RenderArgs& a) {
  render::RenderOptions o;
  try {
    o.field = render::parse_field(a.field);
    if (!a.format.empty()) o.format = render::parse_format(a.format);
    else if (!a.times.empty()) o.format = render::Format::png;
    else if (const auto ext = fs::path(a.output).extension().string(); ext == ".gif" || ext == ".mp4" || ext == ".png")
      o.format = render::parse_format(ext.substr(1));
    if (!a.format.empty() && !a.output.empty()) {
      const auto ext = fs::path(a.output).extension().string();
      if ((ext == ".gif" || ext == ".mp4" || ext == ".png") && ext != render::format_extension(o.format))
        throw render::RenderError(fmt::format("-o {} does not match --format {}", a.output, a.format));
    }
    o.output = a.output;
    o.fps = a.fps;
    if (!a.size.empty()) std::tie(o.width, o.height) = render::parse_size(a.size);
    if (!a.range.empty()) o.range = render::parse_range(a.range);
    if (!a.times.empty()) o.times = render::parse_times(a.times);
    view_from(a, o);
  } catch (const render::RenderError& e) {
    throw BadInput(e.what());
  }
  return o;
}

int render_output(const fs::path& dir, const render::RenderOptions& options, bool quiet) {
  try {
    const auto result = render::render_run(dir, options);
    if (!quiet) std::cout << render::describe(result);
    return 0;
  } catch (const render::RenderError& e) {
    throw BadInput(e.what());
  }
}

}  // namespace

void check_render_field(const std::string& field) {
  try {
    render::parse_field(field);
  } catch (const render::RenderError& e) {
    throw BadInput(fmt::format("--render {}: {}", field, e.what()));
  }
}

void render_after_run(const fs::path& output_dir, const std::string& field, bool quiet) {
  render::RenderOptions o;
  o.field = render::parse_field(field);
  render_output(output_dir, o, quiet);
}

Command add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Draw a run's frames: an animated GIF (default), an MP4 (needs ffmpeg) or PNG snapshots.");
  cmd->add_option("output_dir", args->dir, "A run's output directory (holding frames/frame_NNNNNN.npz)")->required();
  cmd->add_option("--field", args->field, "What colours the water: vx, vy, vz (3D), speed, pressure, density (default: speed)");
  cmd->add_option("--format", args->format,
                  "gif, mp4 or png (default: gif, png with --times, or the extension of -o)");
  cmd->add_option("-o,--output", args->output,
                  "Output file (default: OUTPUT_DIR/<field>.gif or .mp4); for png a directory (default: "
                  "OUTPUT_DIR/snapshots/) or one .png file for one picture");
  cmd->add_option("--fps", args->fps, "Frames per second of the animation (default: 20)");
  cmd->add_option("--size", args->size, "Picture size WIDTHxHEIGHT in pixels (default: fitted to the domain)");
  cmd->add_option("--range", args->range,
                  "Colour range MIN:MAX in the unit on the colour bar (m/s, kPa, kg/m^3); default: from the data, "
                  "the same for every frame");
  cmd->add_option("--times", args->times, "Snapshots only at these times in seconds, e.g. 0,1.5,3 (PNG)");
  cmd->add_option("--view", args->view,
                  "3D runs: the camera's view: iso (default), front (looking along +y), side (along -x), top "
                  "(down z)");
  cmd->add_option("--azimuth", args->azimuth,
                  "3D runs: the camera's azimuth in degrees about the vertical z axis (0: on +x, 90: on +y)");
  cmd->add_option("--elevation", args->elevation, "3D runs: the camera's elevation above the horizontal, -90 to 90");
  cmd->add_option("--slice", args->slice,
                  "3D runs: draw the slab around AXIS=VALUE (e.g. y=0.2) flat, the other two axes (z up)");
  cmd->add_option("--thickness", args->thickness, "The slab's thickness in metres (default: 2 dx)");
  cmd->add_flag("-q,--quiet", args->quiet, "Print nothing on success");
  return {cmd, [args] { return render_output(args->dir, options_from(*args), args->quiet); }};
}

}  // namespace sluice::app
