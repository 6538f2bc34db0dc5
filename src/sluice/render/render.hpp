// Pictures and animations of a run, headless: reads the frames a run wrote
// (OUTPUT_DIR/frames/frame_NNNNNN.npz), draws each with a FrameRenderer on one colour range and one
// view of the domain for the whole run, and writes an animated GIF, an MP4 (through ffmpeg) or PNG
// snapshots.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sluice/render/color_range.hpp"
#include "sluice/render/options.hpp"

namespace sluice::render {

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

// Every frame is read (and a damaged one reported) before anything is written.
RenderResult render_run(const std::filesystem::path& run_dir, const RenderOptions& options);

// One line (or a few for PNG snapshots) saying what was written.
std::string describe(const RenderResult& result);

}  // namespace sluice::render
