// The motion files of a case's moving walls, read when the case is (as its meshes are), so that a
// missing or bad file is an error before a run starts.
#pragma once

#include <string>

#include "sluice/case/case.hpp"
#include "sluice/case/rigid_motion.hpp"

namespace sluice {

// Reads the series of every wall law with law = "file" into its `series`, its path relative to the
// case file's directory (made absolute), or a record built into the binary (data/validation/<file>,
// sluice/case/reference_files.hpp) of that name: first for a built-in case, after the directory for a
// case file; the name of a built-in record stays as written. Throws CaseError naming the wall, the key and the file: a
// file that is missing, unreadable or malformed (geometry/motion.hpp, read_motion_csv), or one that
// ends before time.end with past_end = "error".
void load_motion_files(Case& c, const std::string& source);

}  // namespace sluice
