// "Did you mean ...?": the likely intended name of a misspelt key, section, value or command.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sluice {

// The closest of `candidates` to `word`, if it is close enough to be a likely typo.
std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates);

// Throws the CaseError for an unknown key at `at` (a file position or --set argument), suggesting the
// closest of `candidates`.
[[noreturn]] void fail_unknown_key(const std::string& at, const std::string& key,
                                   const std::vector<std::string>& candidates);

}  // namespace sluice
