// The reference data of data/validation/ (*.csv, provenance lines included), embedded in the binary
// at build time so that `sluice validate` and `sluice analyze` work from any directory.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "sluice/analysis/table.hpp"

namespace sluice::analysis {

struct ReferenceFile {
  std::string name;  // file name, e.g. "buchner2002_p_wall_pysph.csv"
  std::string_view text;
};
const std::vector<ReferenceFile>& reference_files();

// The parsed table of one embedded file; throws AnalysisError if there is no file of that name.
Table reference_table(std::string_view name);

}  // namespace sluice::analysis
