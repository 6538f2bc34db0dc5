// The files of cases/meshes/, defined in the file CMake generates from builtin_meshes.cpp.in.
#pragma once

#include <cstddef>

namespace sluice::detail {

struct BuiltinMeshBytes {
  const char* name;  // relative to cases/: "meshes/<file>"
  const unsigned char* bytes;
  std::size_t size;
};
extern const BuiltinMeshBytes builtin_mesh_files[];  // ends with an entry whose name is null

}  // namespace sluice::detail
