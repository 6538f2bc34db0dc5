#include "sluice/case/value_text.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

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

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (ch == '\n') {
      out += "\\n";
    } else if (ch == '\t') {
      out += "\\t";
    } else if (ch == '\r') {
      out += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(u));
    } else {
      out += ch;
    }
  }
  return out + "\"";
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

}  // namespace sluice
