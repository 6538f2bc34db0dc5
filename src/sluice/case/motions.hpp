// The motion files of a case's moving walls, read when the case is (as its meshes are), so that a
// missing or bad file is an error before a run starts.
#pragma once

#include <string>

#include "sluice/case/case.hpp"

namespace sluice {

// Reads the series of every wall law with law = "file" into its `series`, its path relative to the
// case file's directory (made absolute). Throws CaseError naming the wall, the key and the file: a
// file that is missing, unreadable or malformed (geometry/motion.hpp, read_motion_csv), or one that
// ends before time.end with past_end = "error".
void load_motion_files(Case& c, const std::string& source);

// The prescribed motion of a wall, from its laws (a rotation's degrees made radians).
template <int Dim>
RigidMotion<Dim> rigid_motion_of(const Region& wall);

}  // namespace sluice
