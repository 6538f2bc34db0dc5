#include "sluice/analysis/reference_data.hpp"

#include <fmt/format.h>

namespace sluice::analysis {

Table reference_table(std::string_view name) {
  std::string names;
  for (const auto& f : reference_files()) {
    if (f.name == name) return parse_csv_table(f.text, "data/validation/" + f.name);
    names += (names.empty() ? "" : ", ") + f.name;
  }
  throw AnalysisError(fmt::format("no reference data file '{}'; the embedded files are {}", name, names));
}

}  // namespace sluice::analysis
