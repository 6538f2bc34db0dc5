#include "sluice/case/toml_values.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/case/case_error.hpp"
#include "sluice/case/param_fields.hpp"
#include "sluice/case/suggest.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

// A value as written in a case file: strings quoted (not in toml++'s 'literal' form), numbers in their
// shortest form that reads back the same (0.7, not toml++'s 0.69999999999999996), arrays element by
// element.
std::string value_as_written(const toml::node& n) {
  if (n.is_table()) return "a table";
  if (n.is_string()) return quote(n.as_string()->get());
  if (n.is_floating_point()) {
    std::string s = fmt::format("{}", n.as_floating_point()->get());
    if (s.find_first_not_of("-0123456789") == std::string::npos) s += ".0";  // 2.0 as written, not 2
    return s;
  }
  if (n.is_integer()) return fmt::format("{}", n.as_integer()->get());
  if (n.is_boolean()) return n.as_boolean()->get() ? "true" : "false";
  if (const toml::array* a = n.as_array()) {
    std::string s = "[";
    for (std::size_t k = 0; k < a->size(); ++k) s += (k > 0 ? ", " : "") + value_as_written(*a->get(k));
    return s + "]";
  }
  std::ostringstream out;  // dates and times
  n.visit([&](const auto& v) { out << v; });
  return out.str();
}

// The value as an error message shows it: as written, anything long cut short.
std::string describe_node(const toml::node& n) {
  if (n.is_table()) return "a table";
  if (n.is_array_of_tables()) return "an array of tables";
  std::string s = value_as_written(n);
  if (s.size() > 60) s = n.is_string() ? s.substr(0, 56) + "...\"" : s.substr(0, 57) + "...";
  return s;
}

// A value being read, and what its error messages say about it.
struct Reading {
  const toml::node& node;
  const std::string& at;
  const std::string& key;
  std::string expected;

  [[noreturn]] void fail(const std::string& problem) const {
    throw CaseError(fmt::format("{}: {} = {}: {}; expected {}", at, key, describe_node(node), problem, expected));
  }
};

std::optional<double> as_number(const toml::node& x) {
  if (x.is_floating_point()) return x.as_floating_point()->get();
  if (x.is_integer()) return static_cast<double>(x.as_integer()->get());
  return std::nullopt;
}

void check_range(const Reading& r, double v, double lower, double upper) {
  if (!std::isfinite(v)) r.fail("not a finite number");
  if (lower <= upper && (v < lower || v > upper)) r.fail("out of range");
}

double read_double(const Reading& r, double lower, double upper) {
  const auto v = as_number(r.node);
  if (!v) r.fail("wrong type");
  check_range(r, *v, lower, upper);
  return *v;
}

int read_int(const Reading& r, double lower, double upper) {
  if (!r.node.is_integer()) r.fail("wrong type");
  const auto v = r.node.as_integer()->get();
  if (v < -2147483647LL || v > 2147483647LL) r.fail("out of range");
  check_range(r, static_cast<double>(v), lower, upper);
  return static_cast<int>(v);
}

bool read_bool(const Reading& r) {
  if (!r.node.is_boolean()) r.fail("wrong type");
  return r.node.as_boolean()->get();
}

// A string, one of `choices` unless they are empty.
std::string read_string(const Reading& r, const std::vector<std::string>& choices) {
  if (!r.node.is_string()) r.fail("wrong type");
  const std::string v = r.node.as_string()->get();
  if (!choices.empty() && std::find(choices.begin(), choices.end(), v) == choices.end()) {
    const auto near = closest_match(v, choices);
    r.fail(near ? fmt::format("unknown value (did you mean \"{}\"?)", *near) : "unknown value");
  }
  return v;
}

// `count` finite numbers of the array `a`.
template <int N>
Vec<N> read_components(const Reading& r, const toml::array& a, int count) {
  Vec<N> v{};
  for (int d = 0; d < count; ++d) {
    const auto x = as_number(*a.get(static_cast<std::size_t>(d)));
    if (!x || !std::isfinite(*x)) r.fail("wrong type");
    v[d] = *x;
  }
  return v;
}

Vec3 read_vector(const Reading& r, int dimension) {
  const toml::array* a = r.node.as_array();
  if (a == nullptr) r.fail("wrong type");
  if (a->size() != static_cast<std::size_t>(dimension))
    r.fail(fmt::format("wrong type ({} component{} in a {}D case, domain.dimension = {})", a->size(),
                       a->size() == 1 ? "" : "s", dimension, dimension));
  return read_components<3>(r, *a, dimension);
}

std::vector<Vec2> read_points(const Reading& r) {
  const toml::array* a = r.node.as_array();
  if (a == nullptr) r.fail("wrong type");
  std::vector<Vec2> points;
  for (const auto& item : *a) {
    const toml::array* q = item.as_array();
    if (q == nullptr || q->size() != 2) r.fail("wrong type");
    points.push_back(read_components<2>(r, *q, 2));
  }
  return points;
}

// Finite numbers, at least one, each within [lower, upper] when that is a range.
std::vector<double> read_numbers(const Reading& r, double lower, double upper) {
  const toml::array* a = r.node.as_array();
  if (a == nullptr || a->empty()) r.fail("wrong type");
  std::vector<double> v;
  for (const auto& item : *a) {
    const auto x = as_number(item);
    if (!x || !std::isfinite(*x)) r.fail("wrong type");
    if (lower <= upper && (*x < lower || *x > upper)) r.fail("out of range");
    v.push_back(*x);
  }
  return v;
}

// Distinct strings, each one of `choices`.
std::vector<std::string> read_string_list(const Reading& r, const std::vector<std::string>& choices) {
  const toml::array* a = r.node.as_array();
  if (a == nullptr) r.fail("wrong type");
  std::vector<std::string> v;
  for (const auto& item : *a) {
    if (!item.is_string()) r.fail("wrong type");
    const std::string s = item.as_string()->get();
    if (std::find(choices.begin(), choices.end(), s) == choices.end()) r.fail(fmt::format("unknown entry \"{}\"", s));
    if (std::find(v.begin(), v.end(), s) != v.end()) r.fail(fmt::format("\"{}\" listed twice", s));
    v.push_back(s);
  }
  return v;
}

}  // namespace

template <class Owner>
void assign(Owner& o, const Param<Owner>& p, const toml::node& n, const std::string& at, const std::string& key,
            int dimension) {
  const Reading r{n, at, key, expectation(p, dimension)};
  if (p.only_3d && dimension != 3)
    throw CaseError(fmt::format("{}: {} = {}: a key of 3D cases, and this case is 2D (domain.dimension = {}); leave "
                                "it out, or set domain.dimension = 3",
                                at, key, describe_node(n), dimension));
  std::visit(
      [&](auto member) {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
          member.set(o, choice_index(p, read_string(r, p.choices)));
        } else {
          using T = std::remove_reference_t<decltype(o.*member)>;
          if constexpr (std::is_same_v<T, double>) o.*member = read_double(r, p.lower, p.upper);
          else if constexpr (std::is_same_v<T, int>) o.*member = read_int(r, p.lower, p.upper);
          else if constexpr (std::is_same_v<T, bool>) o.*member = read_bool(r);
          else if constexpr (std::is_same_v<T, std::string>) o.*member = read_string(r, p.choices);
          else if constexpr (std::is_same_v<T, Vec3>) o.*member = read_vector(r, dimension);
          else if constexpr (std::is_same_v<T, std::vector<Vec2>>) o.*member = read_points(r);
          else if constexpr (std::is_same_v<T, std::vector<double>>) o.*member = read_numbers(r, p.lower, p.upper);
          else o.*member = read_string_list(r, p.choices);
        }
      },
      p.field);
}

template void assign(Case&, const Param<Case>&, const toml::node&, const std::string&, const std::string&, int);
template void assign(Region&, const Param<Region>&, const toml::node&, const std::string&, const std::string&, int);
template void assign(Probe&, const Param<Probe>&, const toml::node&, const std::string&, const std::string&, int);
template void assign(MotionLawSpec&, const Param<MotionLawSpec>&, const toml::node&, const std::string&,
                     const std::string&, int);
template void assign(FloatingSpec&, const Param<FloatingSpec>&, const toml::node&, const std::string&,
                     const std::string&, int);

}  // namespace sluice
