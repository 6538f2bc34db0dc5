// The field a Param declares, reached in its owner (a Case, Region or Probe): its current value, its
// default for the case's dimension, and a declaration found by key.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/case/parameter_table.hpp"

namespace sluice {

// The index of `name` among a choice's names; -1 if it is not one of them.
template <class Owner>
int choice_index(const Param<Owner>& p, const std::string& name) {
  const auto it = std::find(p.choices.begin(), p.choices.end(), name);
  return it == p.choices.end() ? -1 : static_cast<int>(it - p.choices.begin());
}

template <class Owner>
const ParamValue& default_in(const Param<Owner>& p, int dimension) {
  return dimension == 3 && !std::holds_alternative<std::monostate>(p.default_3d) ? p.default_3d : p.default_value;
}

// Every declared field of `o` that has a default set to it.
template <class Owner>
void set_defaults(Owner& o, const std::vector<Param<Owner>>& params, int dimension) {
  for (const auto& p : params) {
    const ParamValue& def = default_in(p, dimension);
    std::visit(
        [&](auto member) {
          if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
            if (const auto* name = std::get_if<std::string>(&def)) member.set(o, choice_index(p, *name));
          } else {
            using T = std::remove_reference_t<decltype(o.*member)>;
            if (const T* v = std::get_if<T>(&def)) o.*member = *v;
          }
        },
        p.field);
  }
}

template <class Owner>
ParamValue current_value(const Owner& o, const Param<Owner>& p) {
  return std::visit(
      [&](auto member) -> ParamValue {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>)
          return p.choices[static_cast<std::size_t>(member.get(o))];
        else
          return o.*member;
      },
      p.field);
}

// nullptr if no declaration has that key.
template <class Owner>
const Param<Owner>* find_param(const std::vector<Param<Owner>>& params, std::string_view key) {
  for (const auto& p : params)
    if (p.key == key) return &p;
  return nullptr;
}

}  // namespace sluice
