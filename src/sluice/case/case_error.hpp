// The one error of the case library: a case file or --set override that cannot be accepted.
#pragma once

#include <stdexcept>

namespace sluice {

// The message names where (file:line:column or the --set argument), the key, the value given and
// what was expected.
struct CaseError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace sluice
