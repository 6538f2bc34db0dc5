// The reference data of data/validation/ (embedded in the binary, sluice/case/reference_files.hpp),
// parsed as tables for `sluice validate` and `sluice analyze`.
#pragma once

#include <string_view>

#include "sluice/analysis/table.hpp"
#include "sluice/case/reference_files.hpp"

namespace sluice::analysis {

using sluice::ReferenceFile;
using sluice::reference_files;

// The parsed table of one embedded file; throws AnalysisError if there is no file of that name.
Table reference_table(std::string_view name);

}  // namespace sluice::analysis
