// A closed triangle mesh as a Solid<3>: distances from an AABB tree of its triangles, the inside test
// by ray casting (robust to rays through edges and corners), both from CGAL. CGAL is included by
// mesh_solid.cpp only.
#pragma once

#include <memory>

#include "sluice/geometry/solid.hpp"
#include "sluice/geometry/triangle_mesh.hpp"

namespace sluice {

class MeshSolid final : public Solid<3> {
 public:
  // The mesh must pass check_closed_mesh. Queries are safe from several threads at once.
  explicit MeshSolid(const TriangleMesh& mesh);
  ~MeshSolid() override;
  MeshSolid(const MeshSolid&) = delete;
  MeshSolid& operator=(const MeshSolid&) = delete;

  [[nodiscard]] bool contains(const Vec<3>& x) const override;
  [[nodiscard]] double signed_distance(const Vec<3>& x) const override;
  // The outward normal is along the line from the closest point to x (x outside) or from x to it (x
  // inside); on the surface, the normal of the closest triangle.
  [[nodiscard]] SurfacePoint<3> closest_surface_point(const Vec<3>& x) const override;
  [[nodiscard]] Vec<3> lower() const override { return lower_; }
  [[nodiscard]] Vec<3> upper() const override { return upper_; }
  // The closest point of the surface: a mesh has no faces of its own to list.
  void for_each_face_point(const Vec<3>& x, const std::function<void(const Vec<3>&)>& f) const override;
  // The lattice anchored at the lower corner of the bounding box, keeping the points inside the mesh
  // and within layers x dx of its surface (for a box-shaped mesh, the particles of the same Box).
  void fill_surface_layers(double dx, int layers, const std::function<void(const Vec<3>&)>& add) const override;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
  Vec<3> lower_{}, upper_{};
  double on_surface_ = 0.0;  // distances below this are on the surface
};

}  // namespace sluice
