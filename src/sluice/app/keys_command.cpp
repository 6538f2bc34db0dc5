// sluice keys: every case key as the parameter table declares it (type, unit, default, range,
// description), for a reader and, with --json, for tools (the documentation's case reference, the
// parameter fuzzer in tests/).
#include <fmt/format.h>

#include <iostream>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>

#include <toml++/toml.h>

#include "sluice/app/commands.hpp"
#include "sluice/case/param_fields.hpp"
#include "sluice/case/parameter_table.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice::app {

namespace {

// The kind of value a key takes, as one word.
template <class Owner>
std::string type_of(const Param<Owner>& p) {
  return std::visit(
      [](const auto& field) -> std::string {
        using F = std::decay_t<decltype(field)>;
        if constexpr (std::is_same_v<F, ChoiceField<Owner>>) return "choice";
        else {
          using T = std::remove_cvref_t<decltype(std::declval<Owner&>().*field)>;
          if constexpr (std::is_same_v<T, double>) return "number";
          else if constexpr (std::is_same_v<T, int>) return "integer";
          else if constexpr (std::is_same_v<T, bool>) return "boolean";
          else if constexpr (std::is_same_v<T, std::string>) return "string";
          else if constexpr (std::is_same_v<T, Vec3>) return "vector";
          else if constexpr (std::is_same_v<T, std::vector<std::string>>) return "strings";
          else if constexpr (std::is_same_v<T, std::vector<double>>) return "numbers";
          else return "points";
        }
      },
      p.field);
}

template <class Owner>
toml::table describe(const Param<Owner>& p, const std::string& key, const std::string& section, bool item) {
  toml::table t;
  t.insert("key", key);
  t.insert("section", section);
  t.insert("item", item);
  t.insert("type", type_of(p));
  t.insert("unit", p.unit);
  const bool required = std::holds_alternative<std::monostate>(p.default_value);
  t.insert("required", required);
  if (!required) t.insert("default", format_value(p.default_value, 2));
  if (!std::holds_alternative<std::monostate>(p.default_3d)) t.insert("default_3d", format_value(p.default_3d, 3));
  if (p.lower <= p.upper) {
    t.insert("lower", p.lower);
    t.insert("upper", p.upper);
  }
  toml::array choices;
  for (const auto& c : p.choices) choices.push_back(c);
  t.insert("choices", std::move(choices));
  t.insert("only_3d", p.only_3d);
  t.insert("allowed", expectation(p, 2));
  t.insert("description", p.description);
  return t;
}

// A body's [<section>.translation] and [<section>.rotation] keys: a wall's, or the tank's own walls'.
void add_motion_laws(toml::array& keys, const std::string& section, bool item) {
  for (const bool rotation : {false, true})
    for (const auto& p : motion_law_params(rotation))
      keys.push_back(describe(p, fmt::format("{}.{}.{}", section, rotation ? "rotation" : "translation", p.key),
                              section, item));
}

toml::array all_descriptions() {
  toml::array keys;
  for (const auto& s : case_sections()) {
    if (!s.is_array) {
      for (const auto& p : case_params())
        if (p.key.rfind(s.name + ".", 0) == 0) keys.push_back(describe(p, p.key, s.name, false));
      if (s.name == "tank") add_motion_laws(keys, "tank", false);
    } else if (s.name == "probe") {
      for (const auto& p : probe_params()) keys.push_back(describe(p, s.name + "." + p.key, s.name, true));
    } else if (s.name == "wall") {
      for (const auto& p : wall_params()) keys.push_back(describe(p, s.name + "." + p.key, s.name, true));
      add_motion_laws(keys, "wall", true);
      for (const auto& p : floating_params()) keys.push_back(describe(p, "wall.floating." + p.key, s.name, true));
    } else {
      for (const auto& p : region_params()) keys.push_back(describe(p, s.name + "." + p.key, s.name, true));
    }
  }
  return keys;
}

int list_keys(bool json) {
  const toml::array keys = all_descriptions();
  if (json) {
    std::ostringstream out;
    out << toml::json_formatter{keys} << "\n";
    std::cout << out.str();
    return 0;
  }
  for (const auto& node : keys) {
    const toml::table& t = *node.as_table();
    const std::string unit = t["unit"].value_or(std::string());
    std::cout << fmt::format("{}{}\n    {}\n    {}; {}\n", t["key"].value_or(std::string()),
                             unit.empty() ? "" : " [" + unit + "]", t["description"].value_or(std::string()),
                             t["required"].value_or(false) ? "required" : "default " + t["default"].value_or(std::string()),
                             "allowed: " + t["allowed"].value_or(std::string()));
  }
  return 0;
}

}  // namespace

Command add_keys_command(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("keys", "List every case-file key with its unit, default, range and description.");
  cmd->add_flag("--json", *json, "As a JSON array, one object per key (for tools)");
  return {cmd, [json] { return list_keys(*json); }};
}

}  // namespace sluice::app
