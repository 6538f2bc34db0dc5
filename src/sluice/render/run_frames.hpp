// The frames a run wrote (OUTPUT_DIR/frames/frame_NNNNNN.npz), found and read for drawing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <utility>
#include <vector>

#include "sluice/render/fields.hpp"

namespace sluice::render {

// The frames of a run, in order: (frame number, path of OUTPUT_DIR/frames/frame_NNNNNN.npz).
// RenderError if there are none, FormatError if the numbering has a gap (a missing frame).
std::vector<std::pair<std::int64_t, std::filesystem::path>> list_frames(const std::filesystem::path& run_dir);

// One frame reduced to `field`; FormatError if it is damaged, or its time, spacing or a position is not
// usable (frame_from_npz).
FrameData read_frame(const std::filesystem::path& path, Field field);

}  // namespace sluice::render
