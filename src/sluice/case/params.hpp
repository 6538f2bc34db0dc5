// Case parameters, declared once. Each declaration (key, type, unit, default, range, description)
// drives parsing of case files, `--set` overrides, range checks, error messages, the commented
// template written by `sluice init`, and the parameter reference in the README.
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "sluice/case/case.hpp"

namespace sluice {

// A bad case: the message names where (file:line:column or the --set argument), the key, the value
// given and what was expected.
struct CaseError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A value as the case file writes it. A choice (an enum of the case) is written as its name; a vector
// has as many components as the case has dimensions.
using ParamValue =
    std::variant<std::monostate, double, int, bool, std::string, Vec3, std::vector<std::string>, std::vector<Vec2>>;

// A field of an enum type, reached through its index in the Param's `choices` (which list the names
// in enum order).
template <class Owner>
struct ChoiceField {
  int (*get)(const Owner&);
  void (*set)(Owner&, int);
};

template <class Owner>
struct Param {
  using Field = std::variant<double Owner::*, int Owner::*, bool Owner::*, std::string Owner::*, Vec3 Owner::*,
                             std::vector<std::string> Owner::*, std::vector<Vec2> Owner::*, ChoiceField<Owner>>;
  std::string key;           // "domain.dx" for case keys; "min" for keys of a [[water]] item
  Field field;
  std::string unit;          // "" when dimensionless
  ParamValue default_value;  // monostate: required
  double lower = 0.0;        // inclusive range for numbers (lower > upper: unbounded)
  double upper = -1.0;
  std::vector<std::string> choices;  // allowed strings (empty: any); a ChoiceField's names in enum order
  std::string description;
  ParamValue default_3d{};   // the default in a 3D case where it differs (gravity along -z); else monostate
  bool only_3d = false;      // a key of 3D cases (tank.depth): refused in a 2D case
  // For keys of an item that only some items use (a box's min/max, a polygon's points): whether the
  // key applies to this item. Keys that do not apply are left out of the template.
  bool (*applies)(const Owner&) = nullptr;
};

struct Section {
  std::string name;         // "domain", or "water" for an array of tables [[water]]
  std::string description;
  bool is_array = false;
};

// The declarations, in the order the template lists them.
const std::vector<Section>& case_sections();
const std::vector<Param<Case>>& case_params();
const std::vector<Param<Region>>& region_params();
const std::vector<Param<Probe>>& probe_params();

// Loading. `source` names the text in error messages (a path, or "built-in case 'x'").
Case parse_case(std::string_view toml_text, const std::string& source);
Case load_case_file(const std::filesystem::path& path);

// Applies one "key=value" override (value in TOML syntax; a bare word is taken as a string).
// Keys of array items are written water[0].max (or water.0.max). Validates the case afterwards.
void apply_override(Case& c, std::string_view assignment);

// Applies several overrides, then validates once: overrides that are only valid together (a smaller
// tank and a smaller water region) can be given in any order.
void apply_overrides(Case& c, const std::vector<std::string>& assignments);

// Cross-field checks that single-key ranges cannot express (regions inside the tank, ...).
void validate_case(const Case& c, const std::string& source);

// A fully commented TOML rendering of `c`: every key with its description, unit, default and range.
// parse_case(case_template(c)) gives back c.
std::string case_template(const Case& c);

// Built-in cases (embedded from cases/*.toml at build time).
struct BuiltinCase {
  std::string name;
  std::string_view text;
};
const std::vector<BuiltinCase>& builtin_cases();
std::optional<Case> load_builtin_case(std::string_view name);

// The closest of `candidates` to `word`, if it is close enough to be a likely typo.
std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace sluice
