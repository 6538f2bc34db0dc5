// Checks of a whole case that single-key ranges cannot express: a usable name, water inside the tank,
// shapes that enclose something, distinct probe names, a particle count that fits in memory.
#pragma once

#include <string>

#include "sluice/case/case.hpp"

namespace sluice {

// Throws CaseError "<source>: <what is wrong>" for the first problem found.
void validate_case(const Case& c, const std::string& source);

}  // namespace sluice
