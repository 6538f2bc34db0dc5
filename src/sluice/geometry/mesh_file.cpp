#include "sluice/geometry/mesh_file.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace sluice {

namespace {

std::string lower_extension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  return ext;
}

// assimp keeps coordinates in single precision. The double nearest to the shortest decimal that
// gives back the float: 0.1 where a file says 0.1 (rather than 0.100000001490116), so that a mesh's
// corners fall where its file puts them, on the particle lattice if they are meant to.
double as_written(ai_real x) {
  const std::string shortest = fmt::format("{}", x);
  return std::strtod(shortest.c_str(), nullptr);
}

// Meshes finer than a few million triangles gain nothing at any particle spacing a run can afford, and
// their reading alone (assimp's structures, then the corners joined) takes gigabytes.
constexpr std::size_t kMaxTriangles = 4'000'000;
constexpr std::size_t kMaxMeshBytes = std::size_t{512} << 20;

void check_file_size(std::uintmax_t bytes) {
  if (bytes > kMaxMeshBytes)
    throw MeshError(fmt::format("{} MB; expected a mesh file of at most {} MB (simplify the mesh: detail finer than "
                                "the particle spacing does not reach the particles)",
                                bytes >> 20, kMaxMeshBytes >> 20));
}

// A binary STL is an 80-byte header, a 4-byte triangle count and 50 bytes per triangle. Checked before
// assimp reads it, so that a count that does not match the file (two billion triangles claimed in a
// few bytes) is refused without allocating for it. A file that starts with "solid" and is not of the
// binary size is read as ASCII STL.
void check_binary_stl_size(std::string_view bytes) {
  const std::size_t first = bytes.find_first_not_of(" \t\r\n");
  const bool says_solid = first != std::string_view::npos && bytes.substr(first, 5) == "solid";
  if (bytes.size() < 84) {
    if (says_solid) return;
    throw MeshError(fmt::format("{} bytes, too short for a binary STL (an 84-byte header) and not ASCII STL (which "
                                "starts with \"solid\"); expected a closed triangle mesh",
                                bytes.size()));
  }
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  const std::uint64_t expected = 84 + 50 * std::uint64_t{count};
  if (expected == bytes.size()) {
    if (count > kMaxTriangles)
      throw MeshError(fmt::format("{} triangles; expected at most {} (simplify the mesh: detail finer than the "
                                  "particle spacing does not reach the particles)",
                                  count, kMaxTriangles));
    return;
  }
  if (says_solid) return;
  throw MeshError(fmt::format("a binary STL whose header says {} triangles ({} bytes), in a file of {} bytes; expected "
                              "a complete binary STL, or ASCII STL (which starts with \"solid\")",
                              count, expected, bytes.size()));
}

// An OBJ file's material statements (`mtllib`, `usemtl`) turned into comments: sluice reads geometry
// only, and assimp 5.2 (Debian 12) crashes with a segmentation fault on some `mtllib` lines read from
// memory (found by fuzz_mesh; kept in tests/fuzz_regressions/mesh/obj_mtllib_crashes_assimp and
// obj_mtllib_after_nul). A line ends where assimp's OBJ reader ends one: at \n, \r, \f or a NUL byte.
std::string without_materials(std::string_view bytes) {
  static constexpr std::string_view line_ends("\n\r\f\0", 4);
  std::string text(bytes);
  for (std::size_t line = 0; line < text.size();) {
    std::size_t at = line;
    while (at < text.size() && (text[at] == ' ' || text[at] == '\t')) ++at;
    const std::string_view rest = std::string_view(text).substr(at);
    if (rest.substr(0, 6) == "mtllib" || rest.substr(0, 6) == "usemtl") text[at] = '#';
    const std::size_t end = text.find_first_of(line_ends, at);
    if (end == std::string::npos) break;
    line = end + 1;
  }
  return text;
}

}  // namespace

std::string read_mesh_bytes(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw MeshError("no such file");
  if (std::filesystem::is_directory(path, ec)) throw MeshError("is a directory; expected a mesh file (.stl or .obj)");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec) check_file_size(size);  // before reading it all into memory
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshError("cannot be read");
  if (!ec) {
    // Read into one buffer of the file's size: the file's bytes are held once.
    std::string bytes(static_cast<std::size_t>(size), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(size));
    if (in.bad() || in.gcount() != static_cast<std::streamsize>(size)) throw MeshError("cannot be read");
    return bytes;
  }
  std::ostringstream bytes;  // not a regular file (a pipe): its size is known only once read
  bytes << in.rdbuf();
  if (in.bad()) throw MeshError("cannot be read");
  return bytes.str();
}

TriangleMesh read_mesh(std::string_view bytes, const std::string& name) {
  const std::string ext = lower_extension(name);
  if (ext != "stl" && ext != "obj")
    throw MeshError(fmt::format("unknown mesh format '.{}'; expected a .stl (ASCII or binary) or .obj file", ext));
  if (bytes.empty()) throw MeshError("the file is empty; expected a closed triangle mesh");
  check_file_size(bytes.size());
  if (ext == "stl") check_binary_stl_size(bytes);
  // One importer per thread, kept: making one sets up every format assimp knows, which costs more than
  // reading a small mesh. The scene it holds is freed when this function returns.
  thread_local Assimp::Importer importer;
  struct FreeScene {
    Assimp::Importer& importer;
    ~FreeScene() { importer.FreeScene(); }
  } free_scene{importer};
  // Vertex transforms of the file's node tree are applied, polygons split into triangles; points and
  // lines are kept (and refused below).
  const std::string obj_text = ext == "obj" ? without_materials(bytes) : std::string();
  const std::string_view input = ext == "obj" ? std::string_view(obj_text) : bytes;
  const aiScene* scene = importer.ReadFileFromMemory(
      input.data(), input.size(), aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_ValidateDataStructure,
      ext.c_str());
  if (scene == nullptr) {
    std::string why = importer.GetErrorString();
    // assimp names the bytes read from memory by a made-up file name.
    for (const std::string& made_up : {"$$$___magic___$$$." + ext, std::string("$$$___magic___$$$")})
      for (auto at = why.find(made_up); at != std::string::npos; at = why.find(made_up)) why.replace(at, made_up.size(), "the file");
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ' || why.back() == '.')) why.pop_back();
    throw MeshError(fmt::format("not a readable {} file ({}); expected a closed triangle mesh in {} format",
                                ext == "stl" ? "STL" : "OBJ", why.empty() ? "unknown reason" : why,
                                ext == "stl" ? "ASCII or binary STL" : "Wavefront OBJ"));
  }
  TriangleMesh m;
  std::map<Vec<3>, std::uint32_t> index_of;  // equal corners joined
  // Corner `corner` (from 1) of the next triangle. A NaN would break the map's ordering, and a corner
  // at infinity has no place: each coordinate must be finite.
  auto vertex = [&](const aiVector3D& v, int corner) {
    const Vec<3> p{as_written(v.x), as_written(v.y), as_written(v.z)};
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw MeshError(fmt::format("vertex {} of triangle {} is not finite: ({:g}, {:g}, {:g}); expected three finite "
                                  "coordinates",
                                  corner, m.triangles.size() + 1, p[0], p[1], p[2]));
    const auto [it, added] = index_of.emplace(p, static_cast<std::uint32_t>(m.vertices.size()));
    if (added) m.vertices.push_back(p);
    return it->second;
  };
  std::size_t faces = 0;
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) faces += scene->mMeshes[k]->mNumFaces;
  if (faces > kMaxTriangles)
    throw MeshError(fmt::format("{} triangles; expected at most {} (simplify the mesh: detail finer than the particle "
                                "spacing does not reach the particles)",
                                faces, kMaxTriangles));
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) {
    const aiMesh* mesh = scene->mMeshes[k];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3)
        throw MeshError(fmt::format("it holds a {} (a face with {} corner{}); expected triangles only",
                                    face.mNumIndices == 2 ? "line" : "point", face.mNumIndices,
                                    face.mNumIndices == 1 ? "" : "s"));
      m.triangles.push_back({vertex(mesh->mVertices[face.mIndices[0]], 1),
                             vertex(mesh->mVertices[face.mIndices[1]], 2),
                             vertex(mesh->mVertices[face.mIndices[2]], 3)});
    }
  }
  return m;
}

}  // namespace sluice
