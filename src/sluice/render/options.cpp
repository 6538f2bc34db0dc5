#include "sluice/render/options.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>

#include "sluice/render/render_error.hpp"

namespace sluice::render {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<int> parse_int(std::string_view s) {
  s = trim(s);
  int v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

Format parse_format(std::string_view text) {
  if (text == "gif") return Format::gif;
  if (text == "mp4") return Format::mp4;
  if (text == "png") return Format::png;
  throw RenderError(fmt::format("unknown format '{}'; the formats are gif, mp4, png", text));
}

std::string_view format_extension(Format format) {
  switch (format) {
    case Format::gif: return ".gif";
    case Format::mp4: return ".mp4";
    case Format::png: return ".png";
  }
  return "";
}

Range parse_range(std::string_view text) {
  const auto colon = text.find(':');
  if (colon == std::string_view::npos || text.find(':', colon + 1) != std::string_view::npos)
    throw RenderError(fmt::format("--range '{}': expected MIN:MAX, e.g. 0:5 or -2:2", text));
  const auto lo = parse_double(text.substr(0, colon));
  const auto hi = parse_double(text.substr(colon + 1));
  if (!lo || !hi) throw RenderError(fmt::format("--range '{}': MIN and MAX must be numbers, e.g. 0:5 or -2:2", text));
  if (!(*lo < *hi)) throw RenderError(fmt::format("--range '{}': MIN must be less than MAX", text));
  return {*lo, *hi};
}

std::pair<int, int> parse_size(std::string_view text) {
  const auto x = text.find_first_of("xX");
  const auto w = x == std::string_view::npos ? std::nullopt : parse_int(text.substr(0, x));
  const auto h = x == std::string_view::npos ? std::nullopt : parse_int(text.substr(x + 1));
  if (!w || !h) throw RenderError(fmt::format("--size '{}': expected WIDTHxHEIGHT in pixels, e.g. 1280x720", text));
  if (*w < 160 || *h < 120 || *w > 8192 || *h > 8192)
    throw RenderError(fmt::format("--size '{}': width must be 160 to 8192 and height 120 to 8192 pixels", text));
  return {*w, *h};
}

std::vector<double> parse_times(std::string_view text) {
  std::vector<double> times;
  std::size_t start = 0;
  while (true) {
    const auto comma = text.find(',', start);
    const auto item = text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    const auto t = parse_double(item);
    if (!t || *t < 0.0)
      throw RenderError(fmt::format("--times '{}': '{}' is not a time in seconds (expected t1,t2,..., e.g. 0,1.5,3)",
                                    text, trim(item)));
    times.push_back(*t);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return times;
}

}  // namespace sluice::render
