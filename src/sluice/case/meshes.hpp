// The mesh regions of a case: each [[water]] or [[wall]] of shape "mesh" has its file found, read,
// placed (scale, offset) and checked to be a closed surface.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "sluice/case/case.hpp"

namespace sluice {

// Sets r.mesh of every mesh region of c. A relative file name is looked up in c.mesh_directory (the
// case file's), then among the meshes built into the binary (cases/<file> of the sources); when
// c.mesh_directory is empty (a built-in case), among the built-in meshes first, then in the current
// directory. A file read from disk has its name made absolute, so that the case written into a
// checkpoint finds it again. Throws CaseError "<source>: [[wall]] number N: ..." naming the file and
// what is wrong: a mesh in a 2D case, a missing or unreadable file, one that is not STL or OBJ, or a
// mesh that is empty, open, degenerate, inconsistently oriented or inside out.
void load_meshes(Case& c, const std::string& source);

// The bytes of a mesh built into the binary: cases/<name> of the sources ("meshes/wedge.stl").
std::optional<std::string_view> builtin_mesh(std::string_view name);

}  // namespace sluice
