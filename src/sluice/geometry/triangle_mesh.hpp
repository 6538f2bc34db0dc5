// A closed triangle mesh as plain data: the surface of a 3D solid or water region read from an STL or
// OBJ file (geometry/mesh_file.hpp), checked to enclose a volume (check_closed_mesh), made into a
// Solid<3> by geometry/mesh_solid.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

struct TriangleMesh {
  std::vector<Vec<3>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices, counter-clockwise seen from outside

  [[nodiscard]] Vec<3> lower() const;  // bounding box
  [[nodiscard]] Vec<3> upper() const;
  // The enclosed volume: positive when the triangles are ordered counter-clockwise seen from outside.
  [[nodiscard]] double signed_volume() const;
  // Every vertex v moved to scale * v + offset.
  void place(double scale, const Vec<3>& offset);
};

// A mesh that cannot be used; the message says what is wrong (without the file's name).
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws MeshError unless the mesh encloses a volume: it has triangles, none of them degenerate (two
// equal corners or zero area), it is closed (every edge belongs to exactly two triangles),
// consistently oriented (the two triangles of an edge run along it in opposite directions) and not
// inside out (its signed volume is positive, so its normals point outwards).
void check_closed_mesh(const TriangleMesh& m);

}  // namespace sluice
