// The data files of data/validation/ (*.csv, provenance lines included), embedded in the binary at
// build time: `sluice validate` and `sluice analyze` compare with them from any directory, and a
// built-in case can drive a wall with a recorded motion among them (the NTNU flume's paddle).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace sluice {

struct ReferenceFile {
  std::string name;  // file name, e.g. "buchner2002_p_wall_pysph.csv"
  std::string_view text;
};
const std::vector<ReferenceFile>& reference_files();

// The text of the embedded file of that name, or nullopt.
std::optional<std::string_view> reference_file_text(std::string_view name);

}  // namespace sluice
