// The texts of cases/*.toml, defined in the file CMake generates from builtin_case_texts.cpp.in.
#pragma once

#include <cstddef>

namespace sluice::detail {

struct BuiltinCaseText {
  const char* name;
  const char* text;
};
extern const BuiltinCaseText builtin_case_texts[];
extern const std::size_t builtin_case_count;

}  // namespace sluice::detail
