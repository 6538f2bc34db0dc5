// Case values as TOML text, as the template and the error messages write them, and the words that
// say what a key accepts.
#pragma once

#include <string>

#include "sluice/case/parameter_table.hpp"

namespace sluice {

// A number that reads back as a TOML float: 2 is written 2.0.
std::string format_number(double v);

// A TOML basic string. Control characters are escaped so that any string (a description with a
// newline or a tab, say) reads back unchanged from the template and from checkpoints.
std::string quote(const std::string& s);

// The first `dimension` components, as a TOML array.
std::string format_vector(const Vec3& v, int dimension);

std::string format_value(const ParamValue& v, int dimension);

// What the key accepts, e.g. "a number from 0.0001 to 100 (m)" or "one of \"dynamic\", \"adami\"".
template <class Owner>
std::string expectation(const Param<Owner>& p, int dimension);

}  // namespace sluice
