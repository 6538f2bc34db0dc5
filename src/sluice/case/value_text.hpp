// Case values as TOML text, as the template and the error messages write them, and the words that
// say what a key accepts.
#pragma once

#include <string>
#include <string_view>

#include "sluice/case/parameter_table.hpp"

namespace sluice {

// A number that reads back as a TOML float: 2 is written 2.0.
std::string format_number(double v);

// A TOML basic string. Control characters are escaped so that any string (a description with a
// newline or a tab, say) reads back unchanged from the template and from checkpoints. A byte that is
// not part of a UTF-8 character is written \xFF, which is not TOML: such a string cannot be written
// as a TOML string at all (is_utf8), and a message shows what it holds.
std::string quote(const std::string& s);

// Text read from a file, to be shown in a message: the same escapes as quote() for the control
// characters (C0, DEL and C1, which a terminal may take as commands) and the bytes that are not
// UTF-8, without the surrounding quotes; quotes and backslashes are left as they are.
std::string printable(std::string_view text);

// Whether every byte of `text` belongs to a UTF-8 character.
bool is_utf8(std::string_view text);

// The first `dimension` components, as a TOML array.
std::string format_vector(const Vec3& v, int dimension);

std::string format_value(const ParamValue& v, int dimension);

// What the key accepts, e.g. "a number from 0.0001 to 100 (m)" or "one of \"dynamic\", \"adami\"".
template <class Owner>
std::string expectation(const Param<Owner>& p, int dimension);

}  // namespace sluice
