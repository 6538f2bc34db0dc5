#include "sluice/case/meshes.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "sluice/case/builtin_mesh_bytes.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"
#include "sluice/geometry/mesh_file.hpp"

namespace sluice {


namespace fs = std::filesystem;

std::optional<std::string_view> builtin_mesh(std::string_view name) {
  for (const auto* m = detail::builtin_mesh_files; m->name != nullptr; ++m)
    if (name == m->name) return std::string_view(reinterpret_cast<const char*>(m->bytes), m->size);
  return std::nullopt;
}

namespace {

// Reads, places and checks the mesh of region r; `what` is "[[wall]] number 2" for messages.
void load_mesh(Region& r, const Case& c, const std::string& source, const std::string& what) {
  auto fail = [&](const std::string& file, const std::string& why) {
    throw CaseError(fmt::format("{}: {}: mesh file {}: {}", source, what, file, why));
  };
  if (r.file.empty()) fail(quote(r.file), "no file name; expected the path of an .stl or .obj file");
  const fs::path given(r.file);
  const fs::path path = given.is_absolute() || c.mesh_directory.empty() ? given : fs::path(c.mesh_directory) / given;
  std::error_code ec;
  const bool on_disk = fs::exists(path, ec);
  // A relative name may be a built-in mesh: first for a built-in case, after the case file's directory
  // for a case file (so that `sluice init --from` a case with a mesh gives a case that runs).
  std::optional<std::string_view> built_in;
  if (given.is_relative() && (c.mesh_directory.empty() || !on_disk))
    built_in = builtin_mesh(given.lexically_normal().generic_string());
  std::string bytes;
  std::string shown = quote(r.file);  // how messages name the file
  if (built_in) {
    bytes = std::string(*built_in);
  } else {
    const fs::path absolute = fs::absolute(path, ec).lexically_normal();
    if (path.string() != r.file) shown = fmt::format("{} ({})", quote(r.file), path.string());
    try {
      bytes = read_mesh_bytes(path);
    } catch (const MeshError& e) {
      fail(shown, e.what());
    }
    if (!ec) r.file = absolute.string();
  }
  try {
    TriangleMesh m = read_mesh(bytes, r.file);
    m.place(r.scale, r.offset);
    check_closed_mesh(m);
    r.mesh = std::make_shared<const TriangleMesh>(std::move(m));
  } catch (const MeshError& e) {
    fail(shown, e.what());
  }
}

}  // namespace

void load_meshes(Case& c, const std::string& source) {
  for (auto* regions : {&c.water, &c.walls}) {
    const std::string section = regions == &c.water ? "water" : "wall";
    for (std::size_t i = 0; i < regions->size(); ++i) {
      Region& r = (*regions)[i];
      if (r.shape != Shape::mesh) {
        r.mesh = nullptr;
        continue;
      }
      const std::string what = fmt::format("[[{}]] number {}", section, i + 1);
      if (c.dimension != 3)
        throw CaseError(fmt::format("{}: {}: {}[{}].shape = \"mesh\": a triangle mesh is a 3D shape and this case is "
                                    "{}D; expected shape = \"box\" or \"polygon\"",
                                    source, what, section, i, c.dimension));
      load_mesh(r, c, source, what);
    }
  }
}

}  // namespace sluice
