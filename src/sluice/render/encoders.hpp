// Picture files through libraries: PNG through libpng (palette PNG: exact), GIF through giflib
// (a global 256-colour palette: exact), MP4 through the ffmpeg program, fed raw RGB frames on a pipe.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "sluice/render/image.hpp"

namespace sluice::render {

// Writes `image` as an 8-bit palette PNG file, atomically (IoError on failure).
void write_png(const std::filesystem::path& path, const IndexedImage& image, const Palette& palette);

// An animation being written: frames are added in order, then finish() completes the file. A writer
// destroyed before finish() leaves no file behind.
class AnimationWriter {
 public:
  virtual ~AnimationWriter() = default;
  virtual void add(const IndexedImage& frame) = 0;
  virtual void finish() = 0;
};

// An animated GIF that loops forever, each frame shown for delay_centiseconds (GIF's unit).
std::unique_ptr<AnimationWriter> open_gif(const std::filesystem::path& path, int width, int height,
                                          const Palette& palette, int delay_centiseconds);

// An H.264 MP4 at `fps` frames per second, encoded by ffmpeg (which must be on PATH: see
// find_program). width and height must be even.
std::unique_ptr<AnimationWriter> open_mp4(const std::filesystem::path& path, int width, int height,
                                          const Palette& palette, int fps);

// Throws IoError with a clear message if ffmpeg is not on PATH.
void require_ffmpeg();

// The executable `name` on $PATH, if any.
std::optional<std::filesystem::path> find_program(std::string_view name);

}  // namespace sluice::render
