#include "sluice/case/value_text.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string_view>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace sluice {

std::string format_number(double v) {
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

namespace {

// The code point of the UTF-8 sequence that starts s[at] and its length in bytes; length 0 where the
// bytes there are not UTF-8 (a stray continuation byte, a truncated or overlong sequence, a
// surrogate, past U+10FFFF).
std::pair<char32_t, std::size_t> utf8_at(std::string_view s, std::size_t at) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[at + k]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return {lead, 1};
  // The lead byte gives the length and the code point's first bits (0xC0, 0xC1, 0xF5 and above
  // begin no sequence).
  const std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                             : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
  if (length == 0 || s.size() - at < length) return {0, 0};
  char32_t code = lead & (0x7Fu >> length);
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(k) & 0xC0u) != 0x80u) return {0, 0};
    code = (code << 6) | (byte(k) & 0x3Fu);
  }
  const char32_t least[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < least[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return {0, 0};
  return {code, length};
}

// s with every character that a terminal could take as a command escaped: the C0 controls and DEL
// (\n, \t, \r, else \u001B), the C1 controls U+0080 to U+009F (\u009B) and each byte that is not part
// of a UTF-8 character (\xFF). With `toml_string` also " and \, so that the result between double
// quotes is a TOML basic string.
std::string escaped(std::string_view s, bool toml_string) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t at = 0; at < s.size();) {
    const auto [code, length] = utf8_at(s, at);
    if (length == 0) {
      out += fmt::format("\\x{:02X}", static_cast<unsigned>(static_cast<unsigned char>(s[at])));
      ++at;
      continue;
    }
    if (toml_string && (code == '"' || code == '\\')) {
      out += '\\';
      out += static_cast<char>(code);
    } else if (code == '\n') {
      out += "\\n";
    } else if (code == '\t') {
      out += "\\t";
    } else if (code == '\r') {
      out += "\\r";
    } else if (code < 0x20 || (code >= 0x7F && code <= 0x9F)) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(code));
    } else {
      out.append(s, at, length);
    }
    at += length;
  }
  return out;
}

}  // namespace

std::string quote(const std::string& s) { return '"' + escaped(s, true) + '"'; }

std::string printable(std::string_view text) { return escaped(text, false); }

bool is_utf8(std::string_view text) {
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t length = utf8_at(text, at).second;
    if (length == 0) return false;
    at += length;
  }
  return true;
}

std::string format_vector(const Vec3& v, int dimension) {
  std::vector<std::string> components;
  for (int d = 0; d < dimension; ++d) components.push_back(format_number(v[d]));
  return fmt::format("[{}]", fmt::join(components, ", "));
}

std::string format_value(const ParamValue& v, int dimension) {
  return std::visit(
      [dimension](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) return "(required)";
        else if constexpr (std::is_same_v<T, double>) return format_number(x);
        else if constexpr (std::is_same_v<T, int>) return fmt::format("{}", x);
        else if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>) return quote(x);
        else if constexpr (std::is_same_v<T, Vec3>) return format_vector(x, dimension);
        else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
          std::vector<std::string> pairs;
          for (const Vec2& q : x) pairs.push_back(fmt::format("[{}, {}]", format_number(q[0]), format_number(q[1])));
          return fmt::format("[{}]", fmt::join(pairs, ", "));
        } else if constexpr (std::is_same_v<T, std::vector<double>>) {
          std::vector<std::string> numbers;
          for (const double q : x) numbers.push_back(format_number(q));
          return fmt::format("[{}]", fmt::join(numbers, ", "));
        } else {
          std::vector<std::string> quoted;
          for (const auto& s : x) quoted.push_back(quote(s));
          return fmt::format("[{}]", fmt::join(quoted, ", "));
        }
      },
      v);
}

template <class Owner>
std::string expectation(const Param<Owner>& p, int dimension) {
  const bool ranged = p.lower <= p.upper;
  const std::string unit = p.unit.empty() ? "" : fmt::format(" ({})", p.unit);
  return std::visit(
      [&](auto member) -> std::string {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
          return fmt::format("one of \"{}\"", fmt::join(p.choices, "\", \""));
        } else {
          using T = std::remove_reference_t<decltype(std::declval<Owner&>().*member)>;
          if constexpr (std::is_same_v<T, double>) {
            if (!ranged) return "a number" + unit;
            if (p.upper >= 1e299) return fmt::format("a number >= {}{}", p.lower, unit);
            return fmt::format("a number from {} to {}{}", p.lower, p.upper, unit);
          } else if constexpr (std::is_same_v<T, int>) {
            if (!ranged) return "an integer" + unit;
            if (p.upper >= 1e8) return fmt::format("an integer >= {}{}", p.lower, unit);
            return fmt::format("an integer from {} to {}{}", p.lower, p.upper, unit);
          } else if constexpr (std::is_same_v<T, bool>) {
            return "true or false";
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (p.choices.empty()) return "a string in quotes";
            return fmt::format("one of \"{}\"", fmt::join(p.choices, "\", \""));
          } else if constexpr (std::is_same_v<T, Vec3>) {
            return (dimension == 3 ? "an array of three numbers [x, y, z]" : "an array of two numbers [x, y]") + unit;
          } else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
            return "an array of points [[x, y], ...]" + unit;
          } else if constexpr (std::is_same_v<T, std::vector<double>>) {
            return "an array of one or more numbers [a, b, ...]" + unit;
          } else {
            return fmt::format("an array of strings, each one of \"{}\"", fmt::join(p.choices, "\", \""));
          }
        }
      },
      p.field);
}

template std::string expectation(const Param<Case>&, int);
template std::string expectation(const Param<Region>&, int);
template std::string expectation(const Param<Probe>&, int);
template std::string expectation(const Param<MotionLawSpec>&, int);
template std::string expectation(const Param<FloatingSpec>&, int);

}  // namespace sluice
