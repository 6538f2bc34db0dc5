// A TOML value read into the field a Param declares, with the checks of its declaration (type, range,
// choices, vector length) and error messages that name the key, the value and what it accepts.
#pragma once

#include <string>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

#include "sluice/case/parameter_table.hpp"

namespace sluice {

// Sets p's field of `o` from `n`, or throws CaseError "<at>: <key> = <value>: <problem>; expected ...".
// `at` says where the value was written (file:line:column or the --set argument).
template <class Owner>
void assign(Owner& o, const Param<Owner>& p, const toml::node& n, const std::string& at, const std::string& key,
            int dimension);

}  // namespace sluice
