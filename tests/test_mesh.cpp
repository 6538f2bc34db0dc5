// Triangle meshes from STL and OBJ files: reading (ASCII STL, binary STL and OBJ alike), the checks of
// a closed surface, MeshSolid against Box<3> and an analytic sphere, filling meshes with wall and
// water particles, and the case keys (shape = "mesh", file, scale, offset) with every error they raise.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

#include "sluice/case/meshes.hpp"
#include "sluice/case/params.hpp"
#include "sluice/geometry/box.hpp"
#include "sluice/geometry/mesh_file.hpp"
#include "sluice/geometry/mesh_solid.hpp"
#include "sluice/geometry/setup.hpp"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

// The box [lo, hi] as 12 triangles, counter-clockwise seen from outside.
TriangleMesh box_mesh(const Vec<3>& lo, const Vec<3>& hi) {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) m.vertices.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  // Each face as a quad a b c d, counter-clockwise from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    m.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return m;
}

// A sphere of radius r about c: an icosahedron with each triangle split in four `levels` times, its
// vertices pushed onto the sphere.
TriangleMesh sphere_mesh(const Vec<3>& c, double r, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec<3>> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                 {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                 {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                 {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& p : v) p = (1.0 / norm(p)) * p;
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    auto mid = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      Vec<3> m = 0.5 * (v[a] + v[b]);
      v.push_back((1.0 / norm(m)) * m);
      return middle[key] = static_cast<std::uint32_t>(v.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& tri : f) {
      const std::uint32_t ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
      finer.push_back({tri[0], ab, ca});
      finer.push_back({tri[1], bc, ab});
      finer.push_back({tri[2], ca, bc});
      finer.push_back({ab, bc, ca});
    }
    f = finer;
  }
  TriangleMesh m;
  for (const auto& p : v) m.vertices.push_back(c + r * p);
  m.triangles = f;
  return m;
}

std::string ascii_stl(const TriangleMesh& m) {
  std::string s = "solid test\n";
  for (const auto& t : m.triangles) {
    s += "  facet normal 0 0 0\n    outer loop\n";
    for (auto i : t) s += fmt::format("      vertex {:.17g} {:.17g} {:.17g}\n", m.vertices[i][0], m.vertices[i][1], m.vertices[i][2]);
    s += "    endloop\n  endfacet\n";
  }
  return s + "endsolid test\n";
}

std::string binary_stl(const TriangleMesh& m) {
  std::string s(80, ' ');
  auto put = [&](const void* p, std::size_t n) { s.append(static_cast<const char*>(p), n); };
  const auto count = static_cast<std::uint32_t>(m.triangles.size());
  put(&count, 4);
  for (const auto& t : m.triangles) {
    const float zero[3] = {0, 0, 0};
    put(zero, 12);
    for (auto i : t)
      for (double x : m.vertices[i]) {
        const auto f = static_cast<float>(x);
        put(&f, 4);
      }
    const std::uint16_t attr = 0;
    put(&attr, 2);
  }
  return s;
}

std::string obj(const TriangleMesh& m) {
  std::string s = "# test\no test\n";
  for (const auto& v : m.vertices) s += fmt::format("v {:.17g} {:.17g} {:.17g}\n", v[0], v[1], v[2]);
  for (const auto& t : m.triangles) s += fmt::format("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  return s;
}

// Each triangle as its three corners, rotated to start at the smallest; sorted.
std::vector<std::array<Vec<3>, 3>> triangle_set(const TriangleMesh& m) {
  std::vector<std::array<Vec<3>, 3>> out;
  for (const auto& t : m.triangles) {
    std::array<Vec<3>, 3> p = {m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]};
    std::rotate(p.begin(), std::min_element(p.begin(), p.end()), p.end());
    out.push_back(p);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// An empty directory for the test's files, removed at the end.
class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() / fmt::format("sluice_mesh_{}_{}_{}", ::getpid(), counter++,
                                                   std::chrono::steady_clock::now().time_since_epoch().count());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& bytes) {
    std::ofstream(dir_ / name, std::ios::binary) << bytes;
    return dir_ / name;
  }
  // A 3D case in a 1 m cube tank with the given [[wall]] or [[water]] items after its water, its mesh
  // files looked up in the test's directory.
  Case parse(const std::string& items, int dimension = 3) {
    const std::string water = dimension == 3 ? "[[water]]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 0.2]\n"
                                             : "[[water]]\nmin = [0.0, 0.0]\nmax = [1.0, 0.2]\n";
    const std::string tank = dimension == 3 ? "width = 1.0\ndepth = 1.0\nheight = 1.0\n" : "width = 1.0\nheight = 1.0\n";
    return parse_case(fmt::format("[domain]\ndimension = {}\ndx = 0.05\n[tank]\n{}{}{}", dimension, tank, water, items),
                      "case.toml", dir_.string());
  }
  std::string error_of(const std::string& items, int dimension = 3) {
    try {
      parse(items, dimension);
    } catch (const CaseError& e) {
      return e.what();
    }
    ADD_FAILURE() << "expected a CaseError for\n" << items;
    return "";
  }
  fs::path dir_;
};

void expect_contains(const std::string& text, std::initializer_list<std::string> parts) {
  for (const auto& part : parts)
    EXPECT_NE(text.find(part), std::string::npos) << "text:  " << text << "\nlacks: " << part;
}

std::string wall_mesh(const std::string& file) { return "[[wall]]\nshape = \"mesh\"\nfile = \"" + file + "\"\n"; }

}  // namespace

// ---------------------------------------------------------------------------------------------
// Reading

TEST_F(MeshFiles, AsciiStlBinaryStlAndObjOfTheSameCubeReadTheSame) {
  const TriangleMesh cube = box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0});
  const auto expected = triangle_set(cube);
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::string>>{
           {"cube.stl", ascii_stl(cube)}, {"cube_binary.STL", binary_stl(cube)}, {"cube.obj", obj(cube)}}) {
    SCOPED_TRACE(name);
    const TriangleMesh m = read_mesh(read_mesh_bytes(write(name, bytes)), name);
    EXPECT_EQ(m.vertices.size(), 8u);  // the STL's corners, one per triangle, joined
    EXPECT_EQ(m.triangles.size(), 12u);
    EXPECT_EQ(triangle_set(m), expected);
    EXPECT_NO_THROW(check_closed_mesh(m));
    EXPECT_DOUBLE_EQ(m.signed_volume(), 1.0);
  }
}

TEST(TriangleMesh, ChecksFindEachFlawOfAClosedSurface) {
  auto error = [](const TriangleMesh& m) -> std::string {
    try {
      check_closed_mesh(m);
    } catch (const MeshError& e) {
      return e.what();
    }
    return "no error";
  };
  const TriangleMesh cube = box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0});
  EXPECT_EQ(error(cube), "no error");
  EXPECT_EQ(error(sphere_mesh({0, 0, 0}, 1.0, 2)), "no error");
  expect_contains(error(TriangleMesh{}), {"no triangles"});
  TriangleMesh open = cube;
  open.triangles.pop_back();
  expect_contains(error(open), {"not closed", "belongs to triangle", "only"});
  TriangleMesh inside_out = cube;
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  expect_contains(error(inside_out), {"inside out", "signed volume is -1", "normals point inwards"});
  TriangleMesh one_flipped = cube;
  std::swap(one_flipped.triangles[3][1], one_flipped.triangles[3][2]);
  expect_contains(error(one_flipped), {"runs the same way in triangles", "ordered the same way"});
  TriangleMesh degenerate = cube;
  degenerate.vertices.push_back({0.5, 0.0, 0.0});  // on the edge from corner 0 to corner 1
  degenerate.triangles.push_back({0, 8, 1});
  expect_contains(error(degenerate), {"triangle 13", "degenerate"});
  // Two cubes touching at one corner: every edge has two triangles, but the surface touches itself.
  TriangleMesh touching = cube;
  const TriangleMesh other = box_mesh({1.0, 1.0, 1.0}, {2.0, 2.0, 2.0});
  std::vector<std::uint32_t> index(8);
  for (std::uint32_t k = 0; k < 8; ++k) {
    if (k == 0) index[k] = 7;  // the shared corner
    else {
      index[k] = static_cast<std::uint32_t>(touching.vertices.size());
      touching.vertices.push_back(other.vertices[k]);
    }
  }
  for (const auto& t : other.triangles) touching.triangles.push_back({index[t[0]], index[t[1]], index[t[2]]});
  expect_contains(error(touching), {"touches itself at the corner (1, 1, 1)"});
}

// ---------------------------------------------------------------------------------------------
// MeshSolid

TEST(MeshSolid, UnitCubeAgreesWithBoxOnDistanceInsideClosestPointAndNormal) {
  const Box<3> box({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0});
  const MeshSolid mesh(box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}));
  EXPECT_EQ(mesh.lower(), box.lower());
  EXPECT_EQ(mesh.upper(), box.upper());
  int inside = 0, count = 0;
  // Points inside, outside, off faces, edges and corners; none equally near two faces.
  for (double x = -0.43; x < 1.5; x += 0.137)
    for (double y = -0.51; y < 1.5; y += 0.151)
      for (double z = -0.37; z < 1.5; z += 0.163) {
        const Vec<3> p{x, y, z};
        SCOPED_TRACE(fmt::format("at ({}, {}, {})", x, y, z));
        ++count;
        inside += box.contains(p);
        ASSERT_EQ(mesh.contains(p), box.contains(p));
        ASSERT_NEAR(mesh.signed_distance(p), box.signed_distance(p), 1e-12);
        const SurfacePoint<3> a = mesh.closest_surface_point(p), b = box.closest_surface_point(p);
        for (int d = 0; d < 3; ++d) {
          ASSERT_NEAR(a.point[d], b.point[d], 1e-12);
          ASSERT_NEAR(a.normal[d], b.normal[d], 1e-12);
        }
        std::vector<Vec<3>> faces;
        mesh.for_each_face_point(p, [&](const Vec<3>& q) { faces.push_back(q); });
        ASSERT_EQ(faces.size(), 1u);
        ASSERT_NEAR(norm(faces[0] - b.point), 0.0, 1e-12);
      }
  EXPECT_GT(inside, 100);
  EXPECT_GT(count - inside, 1000);
  // On the surface: not inside, distance 0, the face's normal.
  EXPECT_FALSE(mesh.contains({0.5, 0.5, 1.0}));
  EXPECT_NEAR(mesh.signed_distance({0.5, 0.5, 1.0}), 0.0, 1e-15);
  const SurfacePoint<3> top = mesh.closest_surface_point({0.3, 0.6, 1.0});
  EXPECT_EQ(top.normal, (Vec<3>{0.0, 0.0, 1.0}));
}

TEST(MeshSolid, SphereSignedDistanceIsCloseToTheAnalyticOne) {
  const Vec<3> c{0.5, 0.4, 0.3};
  const double r = 0.25;
  const MeshSolid sphere(sphere_mesh(c, r, 4));  // 5120 triangles: chords within 0.1 % of r
  double worst = 0.0;
  for (double x = 0.0; x < 1.0; x += 0.0731)
    for (double y = 0.0; y < 0.8; y += 0.0677)
      for (double z = 0.0; z < 0.6; z += 0.0593) {
        const Vec<3> p{x, y, z};
        const double exact = norm(p - c) - r;
        worst = std::max(worst, std::abs(sphere.signed_distance(p) - exact));
        if (std::abs(exact) > 0.002) {
          ASSERT_EQ(sphere.contains(p), exact < 0.0);
        }
        const SurfacePoint<3> s = sphere.closest_surface_point(p);
        if (norm(p - c) > 0.05) {
          ASSERT_GT(dot(s.normal, (1.0 / norm(p - c)) * (p - c)), 0.999);
        }
      }
  EXPECT_LT(worst, 0.0015 * r);
}

TEST(MeshSolid, FillingACubeGivesTheParticlesOfTheSameBox) {
  const Vec<3> lo{0.1, 0.2, 0.0}, hi{0.3, 0.4, 0.2};
  const MeshSolid mesh(box_mesh(lo, hi));
  const Box<3> box(lo, hi);
  std::vector<Vec<3>> from_mesh, from_box;
  mesh.fill_surface_layers(0.02, 3, [&](const Vec<3>& x) { from_mesh.push_back(x); });
  box.fill_surface_layers(0.02, 3, [&](const Vec<3>& x) { from_box.push_back(x); });
  EXPECT_EQ(from_mesh.size(), 10u * 10 * 10 - 4 * 4 * 4);  // a 10^3 lattice without its 4^3 core
  ASSERT_EQ(from_mesh.size(), from_box.size());
  for (std::size_t i = 0; i < from_mesh.size(); ++i)
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(from_mesh[i][d], from_box[i][d], 1e-12);
  // A sphere of radius 0.1 at dx = 0.01 in 3 layers: about the volume of the shell over dx^3.
  const MeshSolid sphere(sphere_mesh({0.5, 0.5, 0.5}, 0.1, 4));
  std::size_t n = 0;
  sphere.fill_surface_layers(0.01, 3, [&](const Vec<3>& x) {
    ++n;
    EXPECT_LT(norm(x - Vec<3>{0.5, 0.5, 0.5}), 0.1);
  });
  const double shell = 4.0 / 3.0 * M_PI * (std::pow(0.1, 3) - std::pow(0.07, 3)) / 1e-6;
  EXPECT_NEAR(static_cast<double>(n), shell, 0.05 * shell);
}

// ---------------------------------------------------------------------------------------------
// Case files

TEST_F(MeshFiles, AMeshWallAndAMeshWaterRegionAreReadPlacedAndFilled) {
  write("unit.stl", binary_stl(box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0})));
  write("unit.obj", obj(box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0})));
  const Case c = parse(wall_mesh("unit.stl") + "scale = 0.2\noffset = [0.4, 0.4, 0.0]\n" +
                       "[[water]]\nshape = \"mesh\"\nfile = \"unit.obj\"\nscale = 0.3\noffset = [0.1, 0.6, 0.5]\n");
  ASSERT_EQ(c.walls.size(), 1u);
  ASSERT_NE(c.walls[0].mesh, nullptr);
  EXPECT_EQ(c.walls[0].file, (dir_ / "unit.stl").string());  // made absolute, for a checkpoint's case
  EXPECT_EQ(c.walls[0].mesh->lower(), (Vec<3>{0.4, 0.4, 0.0}));
  EXPECT_DOUBLE_EQ(c.walls[0].mesh->upper()[0], 0.6);
  // The same case with boxes in place of the meshes places the same particles.
  const Case boxes = parse("[[wall]]\nmin = [0.4, 0.4, 0.0]\nmax = [0.6, 0.6, 0.2]\n"
                           "[[water]]\nmin = [0.1, 0.6, 0.5]\nmax = [0.4, 0.9, 0.8]\n");
  const sluice::Setup<3> a = build_setup<3>(c), b = build_setup<3>(boxes);
  ASSERT_EQ(a.particles.size(), b.particles.size());
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < a.particles.size(); ++i) {
    fluid += a.particles.is_fluid(i);
    ASSERT_EQ(a.particles.kind[i], b.particles.kind[i]);
    for (int d = 0; d < 3; ++d) ASSERT_NEAR(a.particles.position[d][i], b.particles.position[d][i], 1e-12);
  }
  EXPECT_EQ(fluid, 20u * 20 * 4 - 4 * 4 * 4 + 6 * 6 * 6);  // the floor layer around the block, and the cube
  // The template names the absolute file and reads back the same mesh without a directory.
  const Case again = parse_case(case_template(c), "stored case");
  EXPECT_EQ(triangle_set(*again.walls[0].mesh), triangle_set(*c.walls[0].mesh));
}

TEST_F(MeshFiles, OverridesChangeTheFileScaleAndOffset) {
  write("unit.stl", ascii_stl(box_mesh({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0})));
  write("big.stl", ascii_stl(box_mesh({0.0, 0.0, 0.0}, {2.0, 2.0, 2.0})));
  Case c = parse(wall_mesh("unit.stl") + "scale = 0.2\n");
  apply_overrides(c, {"wall[0].file=big.stl", "wall[0].offset=[0.5, 0.5, 0.5]"});
  // Relative to the case file's directory, not the current one.
  EXPECT_EQ(c.walls[0].mesh->upper(), (Vec<3>{0.9, 0.9, 0.9}));
  expect_contains(case_template(c), {fmt::format("file = \"{}\"", (dir_ / "big.stl").string()), "scale = 0.2",
                                     "offset = [0.5, 0.5, 0.5]"});
  EXPECT_THROW(apply_override(c, "wall[0].scale=0.3"), CaseError);  // 0.5 + 0.6 > 1: outside the tank
}

TEST_F(MeshFiles, EachBadMeshIsAnErrorNamingTheFileAndWhatWasExpected) {
  const TriangleMesh cube = box_mesh({0.1, 0.1, 0.1}, {0.3, 0.3, 0.3});
  TriangleMesh open = cube, inside_out = cube;
  open.triangles.pop_back();
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  write("open.stl", ascii_stl(open));
  write("inside_out.obj", obj(inside_out));
  write("empty.stl", "");
  write("no_triangles.stl", "solid nothing\nendsolid nothing\n");
  write("garbage.stl", std::string("\x01\x02garbage\xff\xfe not a mesh at all", 30));
  write("garbage.obj", "this is not\x01 an OBJ file\n");
  write("cube.stl", binary_stl(cube));
  write("cube.ply", "ply\n");
  fs::create_directories(dir_ / "folder.stl");

  expect_contains(error_of(wall_mesh("missing.stl")),
                  {"case.toml: [[wall]] number 1: mesh file \"missing.stl\"", (dir_ / "missing.stl").string(), "no such file"});
  expect_contains(error_of(wall_mesh("folder.stl")), {"folder.stl", "is a directory"});
  expect_contains(error_of(wall_mesh("open.stl")),
                  {"open.stl", "it is not closed", "expected a closed surface"});
  expect_contains(error_of("[[water]]\nshape = \"mesh\"\nfile = \"inside_out.obj\"\n"),
                  {"[[water]] number 2: mesh file \"inside_out.obj\"", "inside out", "normals point inwards",
                   "expected a positive volume"});
  expect_contains(error_of(wall_mesh("empty.stl")), {"empty.stl", "the file is empty"});
  const std::string none = error_of(wall_mesh("no_triangles.stl"));
  EXPECT_TRUE(none.find("no triangles") != std::string::npos || none.find("not a readable STL file") != std::string::npos)
      << none;
  const std::string garbage = error_of(wall_mesh("garbage.stl"));
  expect_contains(garbage, {"garbage.stl", "30 bytes, too short for a binary STL (an 84-byte header) and not ASCII STL",
                            "expected a closed triangle mesh"});
  EXPECT_EQ(garbage.find("magic"), std::string::npos) << garbage;
  expect_contains(error_of(wall_mesh("garbage.obj")), {"garbage.obj"});
  expect_contains(error_of(wall_mesh("cube.ply")), {"cube.ply", "expected a .stl"});
  expect_contains(error_of("[[wall]]\nshape = \"mesh\"\n"), {"[[wall]] number 1 has no 'file'"});
  expect_contains(error_of(wall_mesh("cube.stl") + "offset = [0.8, 0.0, 0.0]\n"),
                  {"[[wall]] number 1 (a mesh from [0.9, 0.1, 0.1] to [1.1, 0.3, 0.3]) reaches outside the tank [0, 1] x [0, 1] x [0, 1]"});
  expect_contains(error_of("[[water]]\nshape = \"mesh\"\nfile = \"cube.stl\"\nscale = 4\n"),
                  {"[[water]] number 2 (a mesh from", "reaches outside the tank"});
  expect_contains(error_of(wall_mesh("cube.stl") + "min = [0.0, 0.0, 0.0]\n"),
                  {"gives 'min', which a mesh does not use"});
  expect_contains(error_of(wall_mesh("cube.stl"), 2),
                  {"wall[0].shape = \"mesh\"", "a triangle mesh is a 3D shape and this case is 2D"});
  // A good mesh with all of that fixed.
  EXPECT_NO_THROW(parse(wall_mesh("cube.stl")));
}

// A corner that is not a number (or at infinity) is refused before the corners are joined (a NaN
// in their ordered map broke its ordering), naming the triangle and the corner, in every format.
TEST_F(MeshFiles, NonFiniteVerticesAreRefusedNamingTheVertex) {
  const TriangleMesh cube = box_mesh({0.1, 0.1, 0.1}, {0.3, 0.3, 0.3});
  // The text with its n-th "vertex" line (from 1) replaced by `line`.
  const auto with_vertex = [](std::string text, int n, const std::string& line) {
    std::size_t at = 0;
    for (int k = 0; k < n; ++k) at = text.find("vertex ", at + 1);
    text.replace(at, text.find('\n', at) - at, line);
    return text;
  };
  write("nan.stl", with_vertex(ascii_stl(cube), 10, "vertex nan 0.1 0.3"));
  write("inf.stl", with_vertex(ascii_stl(cube), 6, "vertex 0.1 inf 0.3"));
  TriangleMesh nan_cube = cube;
  nan_cube.vertices[7][2] = std::numeric_limits<double>::quiet_NaN();
  write("nan_binary.stl", binary_stl(nan_cube));
  write("nan.obj", obj(nan_cube));
  expect_contains(error_of(wall_mesh("nan.stl")),
                  {"case.toml: [[wall]] number 1: mesh file \"nan.stl\"",
                   "vertex 1 of triangle 4 is not finite: (nan, 0.1, 0.3); expected three finite coordinates"});
  expect_contains(error_of(wall_mesh("inf.stl")), {"inf.stl", "vertex 3 of triangle 2 is not finite: (0.1, inf, 0.3)"});
  for (const char* file : {"nan_binary.stl", "nan.obj"}) {
    SCOPED_TRACE(file);
    expect_contains(error_of(wall_mesh(file)), {file, "of triangle", "is not finite: (0.3, 0.3, nan)"});
  }
  // A mesh made in memory is checked too: a NaN vertex is not hidden by the bounding box.
  try {
    check_closed_mesh(nan_cube);
    ADD_FAILURE() << "a NaN vertex was accepted";
  } catch (const MeshError& e) {
    expect_contains(e.what(), {"vertex 8 (0.3, 0.3, nan) is not finite"});
  }
}

TEST(MeshCase, ShippedDamBreak3DBuildsWithItsCylinderAndNoWaterInsideAWall) {
  ASSERT_TRUE(builtin_mesh("meshes/cylinder.stl").has_value());
  const Case c = *load_builtin_case("dam_break_3d");
  ASSERT_EQ(c.dimension, 3);
  ASSERT_EQ(c.walls.size(), 1u);
  ASSERT_EQ(c.walls[0].shape, Shape::mesh);
  EXPECT_EQ(c.walls[0].file, "meshes/cylinder.stl");  // found among the built-in meshes
  EXPECT_NEAR(c.walls[0].mesh->lower()[2], 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(c.walls[0].mesh->upper()[2], 0.2);  // the float of the binary STL read as 0.2
  const sluice::Setup<3> s = build_setup<3>(c);
  std::size_t fluid = 0, in_cylinder = 0;
  const auto& cylinder = *s.solids.back();
  for (std::size_t i = 0; i < s.particles.size(); ++i) {
    const Vec<3> x{s.particles.position[0][i], s.particles.position[1][i], s.particles.position[2][i]};
    if (!s.particles.is_fluid(i)) {
      in_cylinder += cylinder.contains(x);
      continue;
    }
    ++fluid;
    for (const auto& solid : s.solids) ASSERT_FALSE(solid->contains(x)) << "fluid particle " << i << " inside a wall";
  }
  EXPECT_EQ(fluid, 20u * 15 * 17);  // the column 0.4 x 0.3 x 0.35 at dx = 0.02 (17 full layers)
  // The cylinder (radius 0.06 m, 0.2 m high) is filled through: its lattice, anchored at the corner
  // of its bounding box, has 6 x 6 points across less the 4 corners (0.05^2 + 0.05^2 > 0.06^2), in 10
  // layers.
  EXPECT_EQ(in_cylinder, 32u * 10);
  EXPECT_GT(s.particles.size(), 10000u);
  EXPECT_LT(s.particles.size(), 30000u);
  // The template of the built-in case reads back.
  EXPECT_NO_THROW(parse_case(case_template(c), "template"));
}
