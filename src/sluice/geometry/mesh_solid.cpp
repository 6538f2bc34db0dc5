#include "sluice/geometry/mesh_solid.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <vector>

#include "sluice/geometry/lattice.hpp"

namespace sluice {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using AabbTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
using Side = CGAL::Side_of_triangle_mesh<Mesh, Kernel>;

Point to_point(const Vec<3>& v) { return {v[0], v[1], v[2]}; }
Vec<3> to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct MeshSolid::Tree {
  Mesh mesh;
  std::vector<Vec<3>> normals;  // of each face, unit, outward
  AabbTree tree;
  std::unique_ptr<Side> side;

  explicit Tree(const TriangleMesh& m) {
    std::vector<Mesh::Vertex_index> v;
    v.reserve(m.vertices.size());
    for (const auto& p : m.vertices) v.push_back(mesh.add_vertex(to_point(p)));
    for (const auto& t : m.triangles) {
      const auto f = mesh.add_face(v[t[0]], v[t[1]], v[t[2]]);
      if (f == Mesh::null_face()) throw MeshError("its triangles do not form a manifold surface");
      const Vec<3> a = m.vertices[t[0]], b = m.vertices[t[1]] - a, c = m.vertices[t[2]] - a;
      const Vec<3> n{b[1] * c[2] - b[2] * c[1], b[2] * c[0] - b[0] * c[2], b[0] * c[1] - b[1] * c[0]};
      normals.push_back((1.0 / norm(n)) * n);
    }
    // Built now, not at the first query: queries then only read it, from any thread.
    tree.insert(faces(mesh).first, faces(mesh).second, mesh);
    tree.build();
    tree.accelerate_distance_queries();
    side = std::make_unique<Side>(tree);
  }
};

MeshSolid::MeshSolid(const TriangleMesh& mesh)
    : tree_(std::make_unique<Tree>(mesh)), lower_(mesh.lower()), upper_(mesh.upper()) {
  on_surface_ = 1e-10 * norm(upper_ - lower_);
}

MeshSolid::~MeshSolid() = default;

bool MeshSolid::contains(const Vec<3>& x) const {
  for (int d = 0; d < 3; ++d)
    if (!(x[d] > lower_[d] && x[d] < upper_[d])) return false;
  return (*tree_->side)(to_point(x)) == CGAL::ON_BOUNDED_SIDE;
}

double MeshSolid::signed_distance(const Vec<3>& x) const {
  const double d = std::sqrt(tree_->tree.squared_distance(to_point(x)));
  return contains(x) ? -d : d;
}

SurfacePoint<3> MeshSolid::closest_surface_point(const Vec<3>& x) const {
  const auto [q, face] = tree_->tree.closest_point_and_primitive(to_point(x));
  SurfacePoint<3> s;
  s.point = to_vec(q);
  const Vec<3> away = x - s.point;
  const double d = norm(away);
  if (d > on_surface_) s.normal = (contains(x) ? -1.0 / d : 1.0 / d) * away;
  else s.normal = tree_->normals[static_cast<std::size_t>(face.idx())];
  return s;
}

void MeshSolid::for_each_face_point(const Vec<3>& x, const std::function<void(const Vec<3>&)>& f) const {
  f(to_vec(tree_->tree.closest_point(to_point(x))));
}

void MeshSolid::fill_surface_layers(double dx, int layers, const std::function<void(const Vec<3>&)>& add) const {
  const double depth = layers * dx;
  for_each_lattice_point<3>(lower_, lower_, upper_, dx, [&](const Vec<3>& x) {
    const double sd = signed_distance(x);
    if (sd < 0.0 && -sd < depth) add(x);
  });
}

}  // namespace sluice
