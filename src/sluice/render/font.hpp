// Text for time stamps, titles and colour-bar labels: glyphs rasterised once by FreeType from a
// TrueType font (DejaVu Sans from the Debian package fonts-dejavu-core by default), then drawn as
// anti-aliased grey levels of the palette. A Font is immutable after construction, so threads
// drawing different pictures may share one.
#pragma once

#include <filesystem>
#include <map>
#include <string_view>
#include <vector>

#include "sluice/render/image.hpp"

namespace sluice::render {

// The font sluice draws with: $SLUICE_FONT if set, else the DejaVu Sans file found at build time.
std::filesystem::path default_font_file();

class Font {
 public:
  // Throws RenderError (render_error.hpp) if the file is missing or not a font FreeType reads.
  Font(const std::filesystem::path& file, int pixel_size);

  [[nodiscard]] int pixel_size() const { return pixel_size_; }
  [[nodiscard]] int text_width(std::string_view utf8) const;
  // Height above the baseline of the digits (for centring numbers on a tick).
  [[nodiscard]] int digit_height() const { return digit_height_; }
  // Draws `utf8` with its baseline at row `baseline`, starting at column x. Glyph coverage is drawn
  // as grey levels up to `darkness` (0..Palette::grey_levels-1) over a white background: draw text
  // on white only.
  void draw(IndexedImage& image, int x, int baseline, std::string_view utf8, int darkness) const;

 private:
  struct Glyph {
    int width = 0, rows = 0, left = 0, top = 0, advance = 0;
    std::vector<std::uint8_t> coverage;
  };
  [[nodiscard]] const Glyph& glyph(char32_t c) const;

  int pixel_size_;
  int digit_height_ = 0;
  std::map<char32_t, Glyph> glyphs_;
};

}  // namespace sluice::render
