// Built-in cases: every cases/*.toml, embedded in the binary at build time, so that a case name works
// from any directory.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "sluice/case/case.hpp"

namespace sluice {

struct BuiltinCase {
  std::string name;
  std::string_view text;
};

// In name order.
const std::vector<BuiltinCase>& builtin_cases();

// The parsed and checked case; nullopt if there is no built-in case of that name.
std::optional<Case> load_builtin_case(std::string_view name);

}  // namespace sluice
