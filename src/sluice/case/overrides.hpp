// `--set key=value` overrides of a case's keys, with the same checks and messages as a case file.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sluice/case/case.hpp"

namespace sluice {

// Applies one "key=value" override (value in TOML syntax; a bare word is taken as a string).
// Keys of array items are written water[0].max (or water.0.max). Validates the case afterwards.
void apply_override(Case& c, std::string_view assignment);

// Applies several overrides, then validates once: overrides that are only valid together (a smaller
// tank and a smaller water region) can be given in any order.
void apply_overrides(Case& c, const std::vector<std::string>& assignments);

}  // namespace sluice
