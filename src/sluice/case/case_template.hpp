// The commented case file `sluice init` writes, and checkpoints store.
#pragma once

#include <string>

#include "sluice/case/case.hpp"

namespace sluice {

// A fully commented TOML rendering of `c`: every key with its description, unit, default and range.
// parse_case(case_template(c)) gives back c.
std::string case_template(const Case& c);

}  // namespace sluice
