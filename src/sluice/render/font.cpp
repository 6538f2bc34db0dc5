#include "sluice/render/font.hpp"

#include <ft2build.h>
#include FT_FREETYPE_H
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "sluice/render/render_error.hpp"

#ifndef SLUICE_FONT_FILE
#error "SLUICE_FONT_FILE must name the default TrueType font (set by CMake)"
#endif

namespace sluice::render {

std::filesystem::path default_font_file() {
  if (const char* env = std::getenv("SLUICE_FONT"); env && *env) return env;
  return SLUICE_FONT_FILE;
}

namespace {

// Decodes UTF-8 (invalid bytes become U+FFFD).
std::u32string decode_utf8(std::string_view s) {
  std::u32string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const int extra = b < 0x80 ? 0 : (b >> 5) == 0x6 ? 1 : (b >> 4) == 0xE ? 2 : (b >> 3) == 0x1E ? 3 : -1;
    if (extra < 0) {
      out.push_back(U'\uFFFD');
      ++i;
      continue;
    }
    char32_t c = extra == 0 ? b : (b & (0x3F >> extra));
    bool ok = true;
    for (int k = 1; k <= extra; ++k) {
      if (i + k >= s.size() || (static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) {
        ok = false;
        break;
      }
      c = (c << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    }
    if (!ok) {
      out.push_back(U'\uFFFD');
      ++i;
      continue;
    }
    out.push_back(c);
    i += extra + 1;
  }
  return out;
}

// Everything sluice writes: printable ASCII and a few symbols of units and labels.
std::u32string wanted_characters() {
  std::u32string s;
  for (char32_t c = 32; c < 127; ++c) s.push_back(c);
  s += U"\u00B3\u00B7\u2212\u2013\u2014\u03C1\u00B0\uFFFD";  // ³ · − – — ρ ° replacement
  return s;
}

}  // namespace

Font::Font(const std::filesystem::path& file, int pixel_size) : pixel_size_(pixel_size) {
  FT_Library library = nullptr;
  if (FT_Init_FreeType(&library) != 0) throw RenderError("FreeType could not be initialised");
  FT_Face face = nullptr;
  if (FT_New_Face(library, file.c_str(), 0, &face) != 0) {
    FT_Done_FreeType(library);
    std::error_code ec;
    throw RenderError(std::filesystem::exists(file, ec)
                          ? fmt::format("{}: not a font FreeType can read", file.string())
                          : fmt::format("{}: font file not found (install the Debian package fonts-dejavu-core, or "
                                        "set SLUICE_FONT to a .ttf file)",
                                        file.string()));
  }
  FT_Set_Pixel_Sizes(face, 0, static_cast<FT_UInt>(pixel_size));
  for (const char32_t c : wanted_characters()) {
    const FT_UInt index = FT_Get_Char_Index(face, c);
    if (index == 0 && c != U' ') continue;
    if (FT_Load_Glyph(face, index, FT_LOAD_DEFAULT) != 0 || FT_Render_Glyph(face->glyph, FT_RENDER_MODE_NORMAL) != 0)
      continue;
    const FT_GlyphSlot slot = face->glyph;
    Glyph g;
    g.width = static_cast<int>(slot->bitmap.width);
    g.rows = static_cast<int>(slot->bitmap.rows);
    g.left = slot->bitmap_left;
    g.top = slot->bitmap_top;
    g.advance = static_cast<int>(std::lround(static_cast<double>(slot->advance.x) / 64.0));
    g.coverage.resize(static_cast<std::size_t>(g.width) * g.rows);
    for (int r = 0; r < g.rows; ++r)
      std::copy_n(slot->bitmap.buffer + static_cast<std::ptrdiff_t>(r) * slot->bitmap.pitch, g.width,
                  g.coverage.begin() + static_cast<std::ptrdiff_t>(r) * g.width);
    glyphs_[c] = std::move(g);
  }
  FT_Done_Face(face);
  FT_Done_FreeType(library);
  if (!glyphs_.contains(U'0') || !glyphs_.contains(U'\uFFFD'))
    throw RenderError(fmt::format("{}: the font lacks digits or U+FFFD", file.string()));
  digit_height_ = glyphs_.at(U'0').top;
}

const Font::Glyph& Font::glyph(char32_t c) const {
  const auto it = glyphs_.find(c);
  return it != glyphs_.end() ? it->second : glyphs_.at(U'\uFFFD');
}

int Font::text_width(std::string_view utf8) const {
  int w = 0;
  for (const char32_t c : decode_utf8(utf8)) w += glyph(c).advance;
  return w;
}

void Font::draw(IndexedImage& image, int x, int baseline, std::string_view utf8, int darkness) const {
  for (const char32_t c : decode_utf8(utf8)) {
    const Glyph& g = glyph(c);
    for (int r = 0; r < g.rows; ++r) {
      const int y = baseline - g.top + r;
      if (y < 0 || y >= image.height) continue;
      for (int k = 0; k < g.width; ++k) {
        const int px = x + g.left + k;
        if (px < 0 || px >= image.width) continue;
        const int cov = g.coverage[static_cast<std::size_t>(r) * g.width + k];
        if (cov == 0) continue;
        const int level = (cov * darkness + 127) / 255;
        std::uint8_t& p = image.at(px, y);
        // Overlapping glyph edges keep the darker grey.
        const int current = p >= Palette::white ? p - Palette::white : 0;
        if (level > current) p = Palette::grey(level);
      }
    }
    x += g.advance;
  }
}

}  // namespace sluice::render
