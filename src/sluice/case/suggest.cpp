#include "sluice/case/suggest.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

// Levenshtein distance: insertions, deletions and substitutions of one character each count 1.
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// How far `word` is from `candidate`, with the shortcuts a user takes counted as near.
std::size_t distance_to(std::string_view word, std::string_view candidate) {
  // Compare with the whole key and with its last part, so "domain.ddx" and "ddx" both find "domain.dx".
  std::size_t d = edit_distance(word, candidate);
  const auto dot_pos = candidate.rfind('.');
  if (dot_pos != std::string_view::npos && word.find('.') == std::string_view::npos)
    d = std::min(d, edit_distance(word, candidate.substr(dot_pos + 1)));
  // A word that is the start of a candidate ("wendland" for "wendland_c2") is a likely abbreviation.
  if (word.size() >= 3 && candidate.starts_with(word)) d = std::min<std::size_t>(d, 1);
  return d;
}

}  // namespace

std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = distance_to(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

void fail_unknown_key(const std::string& at, const std::string& key, const std::vector<std::string>& candidates) {
  const auto near = closest_match(key, candidates);
  if (near) throw CaseError(fmt::format("{}: unknown key '{}'; did you mean '{}'?", at, printable(key), *near));
  throw CaseError(fmt::format("{}: unknown key '{}'; see `sluice init` for every key", at, printable(key)));
}

}  // namespace sluice
