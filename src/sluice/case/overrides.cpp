#include "sluice/case/overrides.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <limits>
#include <optional>
#include <regex>

#include "sluice/case/case_error.hpp"
#include "sluice/case/checks.hpp"
#include "sluice/case/meshes.hpp"
#include "sluice/case/motions.hpp"
#include "sluice/case/param_fields.hpp"
#include "sluice/case/suggest.hpp"
#include "sluice/case/toml_values.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

// Without the leading and trailing characters of `blanks` (by default, C's isspace).
std::string trim(std::string_view s, std::string_view blanks = " \t\n\v\f\r") {
  const auto first = s.find_first_not_of(blanks);
  if (first == std::string_view::npos) return {};
  return std::string(s.substr(first, s.find_last_not_of(blanks) - first + 1));
}

// "npz, 'vtk'" or "[npz, vtk]" as a TOML array of strings; empty items are dropped.
toml::array bare_string_list(std::string_view list) {
  if (list.size() >= 2 && list.front() == '[' && list.back() == ']') list = list.substr(1, list.size() - 2);
  toml::array items;
  while (true) {
    const auto comma = list.find(',');
    std::string item = trim(list.substr(0, comma), " \t");
    if (item.size() >= 2 && (item.front() == '"' || item.front() == '\'') && item.back() == item.front())
      item = item.substr(1, item.size() - 2);
    if (!item.empty()) items.push_back(item);
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return items;
}

// The text as one TOML value, if it is one ("1\nother = 2" is not).
std::optional<toml::table> parse_value(const std::string& text) {
  try {
    const std::string document = "value = " + text;
    toml::table t = toml::parse(std::string_view(document), std::string_view("--set"));
    if (t.size() == 1 && t.contains("value")) return t;
  } catch (const toml::parse_error&) {
  }
  return std::nullopt;
}

// The value of `--set key=text` for parameter p, as a TOML node held under "value" in the returned
// table. The text is TOML ("0.1", "[3.0, 4.0]", "\"euler\""); a bare word is taken as a string, so
// time.integrator=euler and case.name=2024 mean the strings, and a string list may be written bare
// (output.formats=npz,vtk or [npz, vtk]) since shells strip the quotes from ["npz", "vtk"].
template <class Owner>
toml::table override_value(const Param<Owner>& p, const std::string& text, const std::string& at, int dimension) {
  if (text.empty())
    throw CaseError(fmt::format("{}: no value after '='; expected {}", at, expectation(p, dimension)));
  const std::optional<toml::table> parsed = parse_value(text);
  const bool quoted = text.front() == '"' || text.front() == '\'';
  if (std::holds_alternative<std::string Owner::*>(p.field) || std::holds_alternative<ChoiceField<Owner>>(p.field)) {
    if (parsed && parsed->get("value")->is_string()) return *parsed;
    if (!quoted) return toml::table{{"value", text}};
  } else if (std::holds_alternative<std::vector<std::string> Owner::*>(p.field)) {
    if (parsed && parsed->get("value")->is_array()) return *parsed;
    return toml::table{{"value", bare_string_list(text)}};
  }
  if (parsed) return *parsed;
  return toml::table{{"value", text}};  // not TOML: shown as given in the "wrong type" message
}

// Sets p's field of `o` from the text of `--set key=text`.
template <class Owner>
void set_from_text(Owner& o, const Param<Owner>& p, const std::string& text, const std::string& at,
                   const std::string& key, int dimension) {
  const toml::table holder = override_value(p, text, at, dimension);
  assign(o, p, *holder.get("value"), at, key, dimension);
}

// One `--set` argument: where it is (for messages), its key and its value's text.
struct Assignment {
  std::string at, key, text;
};

Assignment split_assignment(std::string_view assignment) {
  // A case file is UTF-8 (TOML), and so is the case a checkpoint stores: a string holding other bytes
  // cannot be written there as TOML, and the run could not be restarted from its checkpoint.
  if (!is_utf8(assignment))
    throw CaseError(fmt::format("--set {}: not UTF-8 text; expected the key and value as UTF-8, as in a case file",
                                printable(assignment)));
  Assignment a;
  a.at = fmt::format("--set {}", assignment);
  const auto eq = assignment.find('=');
  if (eq == std::string_view::npos)
    throw CaseError(fmt::format("{}: expected key=value, for example --set domain.dx=0.1", a.at));
  a.key = trim(assignment.substr(0, eq));
  a.text = trim(assignment.substr(eq + 1));
  if (a.key.empty())
    throw CaseError(fmt::format("{}: no key before '='; expected key=value, for example --set domain.dx=0.1", a.at));
  return a;
}

// A key of entry `digits` of [[section]]: water[1].max or water.1.max.
template <class Owner>
void set_item_key(std::vector<Owner>& items, const std::vector<Param<Owner>>& params, const Assignment& a,
                  const std::string& section, const std::string& digits, const std::string& sub, int dimension) {
  // Compare as text first: an index too long for an integer is simply out of range.
  const std::size_t index = digits.size() > 9 ? std::numeric_limits<std::size_t>::max() : std::stoul(digits);
  if (index >= items.size())
    throw CaseError(fmt::format("{}: the case has {} [[{}]] entr{} (numbered from 0); there is no {}[{}]", a.at,
                                items.size(), section, items.size() == 1 ? "y" : "ies", section, digits));
  const auto* p = find_param(params, sub);
  if (p == nullptr) {
    std::vector<std::string> candidates;
    for (const auto& q : params) candidates.push_back(q.key);
    const auto near = closest_match(sub, candidates);
    throw CaseError(fmt::format("{}: unknown key '{}' in [[{}]]; {}", a.at, sub, section,
                                near ? fmt::format("did you mean '{}[{}].{}'?", section, digits, *near)
                                     : fmt::format("expected one of: {}", fmt::join(candidates, ", "))));
  }
  set_from_text(items[index], *p, a.text, a.at, a.key, dimension);
}

void set_case_key(Case& c, const Assignment& a) {
  const auto* p = find_param(case_params(), a.key);
  if (p == nullptr) fail_unknown_key(a.at, a.key, all_keys());
  // Every vector of the case and its defaults follow the dimension: it is the case file's to say.
  if (a.key == "domain.dimension")
    throw CaseError(fmt::format("{}: the dimension cannot be changed with --set (the case's vectors and defaults "
                                "follow it); write domain.dimension in the case file",
                                a.at));
  set_from_text(c, *p, a.text, a.at, a.key, c.dimension);
}

void apply_one_override(Case& c, std::string_view assignment) {
  const Assignment a = split_assignment(assignment);
  static const std::regex item_key(R"(^(water|wall|probe)(?:\[(\d+)\]|\.(\d+))\.(\w+)$)");
  static const std::regex law_key(R"(^wall(?:\[(\d+)\]|\.(\d+))\.(translation|rotation)\.(\w+)$)");
  static const std::regex tank_law_key(R"(^tank\.(translation|rotation)\.(\w+)$)");
  static const std::regex floating_key(R"(^wall(?:\[(\d+)\]|\.(\d+))\.floating\.(\w+)$)");
  std::smatch m;
  if (std::regex_match(a.key, m, floating_key)) {
    const std::string digits = m[1].matched ? m[1].str() : m[2].str();
    const std::size_t index = digits.size() > 9 ? std::numeric_limits<std::size_t>::max() : std::stoul(digits);
    if (index >= c.walls.size())
      throw CaseError(fmt::format("{}: the case has {} [[wall]] entr{} (numbered from 0); there is no wall[{}]", a.at,
                                  c.walls.size(), c.walls.size() == 1 ? "y" : "ies", digits));
    std::vector<FloatingSpec> floating{c.walls[index].floating};
    set_item_key(floating, floating_params(), a, "wall.floating", "0", m[3], c.dimension);
    c.walls[index].floating = floating[0];
    c.walls[index].floats = true;
    return;
  }
  if (std::regex_match(a.key, m, tank_law_key)) {
    const bool rotation = m[1] == "rotation";
    const auto& params = motion_law_params(rotation);
    const auto* p = find_param(params, m[2].str());
    if (p == nullptr) {
      std::vector<std::string> candidates;
      for (const auto& q : params) candidates.push_back(q.key);
      const auto near = closest_match(m[2].str(), candidates);
      throw CaseError(fmt::format("{}: unknown key '{}' in [tank.{}]; {}", a.at, m[2].str(), m[1].str(),
                                  near ? fmt::format("did you mean 'tank.{}.{}'?", m[1].str(), *near)
                                       : fmt::format("expected one of: {}", fmt::join(candidates, ", "))));
    }
    set_from_text(rotation ? c.tank_rotation : c.tank_translation, *p, a.text, a.at, a.key, c.dimension);
    return;
  }
  if (std::regex_match(a.key, m, law_key)) {
    const std::string digits = m[1].matched ? m[1].str() : m[2].str();
    const bool rotation = m[3] == "rotation";
    const std::size_t index = digits.size() > 9 ? std::numeric_limits<std::size_t>::max() : std::stoul(digits);
    if (index >= c.walls.size())
      throw CaseError(fmt::format("{}: the case has {} [[wall]] entr{} (numbered from 0); there is no wall[{}]", a.at,
                                  c.walls.size(), c.walls.size() == 1 ? "y" : "ies", digits));
    std::vector<MotionLawSpec> law{rotation ? c.walls[index].rotation : c.walls[index].translation};
    set_item_key(law, motion_law_params(rotation), a, fmt::format("wall.{}", m[3].str()), "0", m[4], c.dimension);
    (rotation ? c.walls[index].rotation : c.walls[index].translation) = law[0];
    return;
  }
  if (!std::regex_match(a.key, m, item_key)) return set_case_key(c, a);
  const std::string section = m[1];
  const std::string digits = m[2].matched ? m[2].str() : m[3].str();
  const std::string sub = m[4];
  if (section == "water") set_item_key(c.water, region_params(), a, section, digits, sub, c.dimension);
  else if (section == "wall") set_item_key(c.walls, wall_params(), a, section, digits, sub, c.dimension);
  else set_item_key(c.probes, probe_params(), a, section, digits, sub, c.dimension);
}

}  // namespace

void apply_override(Case& c, std::string_view assignment) {
  apply_one_override(c, assignment);
  load_meshes(c, fmt::format("--set {}", assignment));
  load_motion_files(c, fmt::format("--set {}", assignment));
  validate_case(c, fmt::format("--set {}", assignment));
}

void apply_overrides(Case& c, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) apply_one_override(c, a);
  if (!assignments.empty()) {
    const std::string source = fmt::format("with --set {}", fmt::join(assignments, " --set "));
    load_meshes(c, source);
    load_motion_files(c, source);
    validate_case(c, source);
  }
}

}  // namespace sluice
