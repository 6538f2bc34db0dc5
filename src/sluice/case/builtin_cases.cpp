#include "sluice/case/builtin_cases.hpp"

#include <fmt/format.h>

#include "sluice/case/builtin_case_texts.hpp"
#include "sluice/case/load.hpp"

namespace sluice {

const std::vector<BuiltinCase>& builtin_cases() {
  static const std::vector<BuiltinCase> cases = [] {
    std::vector<BuiltinCase> v;
    for (std::size_t i = 0; i < detail::builtin_case_count; ++i)
      v.push_back({detail::builtin_case_texts[i].name, detail::builtin_case_texts[i].text});
    return v;
  }();
  return cases;
}

std::optional<Case> load_builtin_case(std::string_view name) {
  for (const auto& b : builtin_cases())
    if (b.name == name) return parse_case(b.text, fmt::format("built-in case '{}'", b.name));
  return std::nullopt;
}

}  // namespace sluice
