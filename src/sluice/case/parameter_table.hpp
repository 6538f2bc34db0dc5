// Case parameters, declared once. Each declaration (key, type, unit, default, range, description)
// drives parsing of case files, `--set` overrides, range checks, error messages and the commented
// template written by `sluice init`.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "sluice/case/case.hpp"

namespace sluice {

// A value as the case file writes it. A choice (an enum of the case) is written as its name; a vector
// has as many components as the case has dimensions.
using ParamValue =
    std::variant<std::monostate, double, int, bool, std::string, Vec3, std::vector<std::string>, std::vector<Vec2>,
                 std::vector<double>>;

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
                             std::vector<std::string> Owner::*, std::vector<Vec2> Owner::*,
                             std::vector<double> Owner::*, ChoiceField<Owner>>;
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
  bool optional = false;  // with `applies`: the items it applies to may leave it out (its default is used)
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
// The keys of a [[wall]]: a region's and the body's own (name).
const std::vector<Param<Region>>& wall_params();
// The keys of a wall's [wall.translation] (rotation = false) and [wall.rotation] tables.
const std::vector<Param<MotionLawSpec>>& motion_law_params(bool rotation);
// The keys of a floating wall's [wall.floating] table.
const std::vector<Param<FloatingSpec>>& floating_params();
const std::vector<Param<Probe>>& probe_params();

// Every key as an error message names it: "domain.dx", and "water.min", "probe.name" for the keys of
// array items.
std::vector<std::string> all_keys();

}  // namespace sluice
