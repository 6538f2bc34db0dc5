// Reading triangle meshes from STL (ASCII or binary) and Wavefront OBJ files, through assimp. The
// corners of adjacent triangles, written once per triangle in STL, are joined where they are equal.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sluice/geometry/triangle_mesh.hpp"

namespace sluice {

// The mesh in `bytes`, whose format follows the extension of `name` (.stl or .obj, any case). Throws
// MeshError (the message without the name) if it is not a mesh of that format. The mesh is not
// checked to be closed (check_closed_mesh).
TriangleMesh read_mesh(std::string_view bytes, const std::string& name);

// The file's bytes; MeshError if it does not exist or cannot be read.
std::string read_mesh_bytes(const std::filesystem::path& path);

}  // namespace sluice
