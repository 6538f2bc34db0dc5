#include "sluice/io/frames.hpp"

#include <fmt/format.h>

#include <numeric>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"

namespace sluice {

Frame make_frame(const Simulation& sim) {
  Frame f;
  f.time = sim.time();
  f.step = sim.clock().step;
  f.dx = sim.config().dx;
  f.dimension = sim.dimension();
  sim.visit([&](const auto& solver) {
    const auto& p = solver.particles();
    constexpr int dim = std::decay_t<decltype(p)>::dim;
    const std::size_t n = p.size();
    f.position.resize(dim * n);
    f.velocity.resize(dim * n);
    f.density.resize(n);
    f.pressure.resize(n);
    f.kind.resize(n);
    f.id.resize(n);
    // Ids are 0..n-1; place each particle at the row of its id.
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t row = p.id[i];
      for (int d = 0; d < dim; ++d) {
        f.position[dim * row + d] = p.position[d][i];
        f.velocity[dim * row + d] = p.velocity[d][i];
      }
      f.density[row] = p.density[i];
      f.pressure[row] = solver.eos().pressure(p.density[i]);
      f.kind[row] = static_cast<std::uint8_t>(p.kind[i]);
      f.id[row] = p.id[i];
    }
  });
  return f;
}

std::string frame_to_npz(const Frame& f) {
  const std::size_t n = f.size();
  return make_npz({
      {"t", NpyArray::of(std::vector<double>{f.time}, {})},
      {"step", NpyArray::of(std::vector<std::int64_t>{f.step}, {})},
      {"dx", NpyArray::of(std::vector<double>{f.dx}, {})},
      {"x", NpyArray::of(f.position, {n, static_cast<std::size_t>(f.dimension)})},
      {"v", NpyArray::of(f.velocity, {n, static_cast<std::size_t>(f.dimension)})},
      {"rho", NpyArray::of(f.density, {n})},
      {"p", NpyArray::of(f.pressure, {n})},
      {"kind", NpyArray::of(f.kind, {n})},
      {"id", NpyArray::of(f.id, {n})},
  });
}

Frame frame_from_npz(const std::string& bytes, const std::string& source) {
  try {
    const auto arrays = parse_npz(bytes);
    auto array = [&](const std::string& name) -> const NpyArray& {
      const auto it = arrays.find(name);
      if (it == arrays.end()) throw FormatError(fmt::format("no array '{}'", name));
      return it->second;
    };
    auto scalar = [&](const std::string& name) {
      const auto v = array(name).values<double>();
      if (v.size() != 1) throw FormatError(fmt::format("'{}' is not a scalar", name));
      return v[0];
    };
    Frame f;
    f.time = scalar("t");
    f.dx = scalar("dx");
    const auto step = array("step").values<std::int64_t>();
    if (step.size() != 1) throw FormatError("'step' is not a scalar");
    f.step = step[0];
    f.position = array("x").values<double>();
    f.velocity = array("v").values<double>();
    f.density = array("rho").values<double>();
    f.pressure = array("p").values<double>();
    f.kind = array("kind").values<std::uint8_t>();
    f.id = array("id").values<std::uint32_t>();
    const std::size_t n = f.density.size();
    const auto& x_shape = array("x").shape;
    if (x_shape.size() != 2 || (x_shape[1] != 2 && x_shape[1] != 3))
      throw FormatError("'x' is not an array of 2D or 3D positions (N x 2 or N x 3)");
    f.dimension = static_cast<int>(x_shape[1]);
    const std::size_t dim = x_shape[1];
    if (f.position.size() != dim * n || f.velocity.size() != dim * n || f.pressure.size() != n ||
        f.kind.size() != n || f.id.size() != n)
      throw FormatError("arrays have inconsistent lengths");
    return f;
  } catch (const FormatError& e) {
    throw FormatError(fmt::format("{}: not a sluice frame: {}", source, e.what()));
  }
}

Frame read_npz_frame(const std::filesystem::path& path) {
  return frame_from_npz(read_file(path), path.string());
}

namespace {

struct AppendedArray {
  std::string name;
  std::string type;  // VTK type name
  int components;
  std::string bytes;
};

template <class T>
std::string raw_bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

}  // namespace

std::string frame_to_vtu(const Frame& f) {
  const std::size_t n = f.size();
  std::vector<double> points(3 * n, 0.0), velocity(3 * n, 0.0);
  const std::size_t dim = static_cast<std::size_t>(f.dimension);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t d = 0; d < dim; ++d) {
      points[3 * i + d] = f.position[dim * i + d];
      velocity[3 * i + d] = f.velocity[dim * i + d];
    }
  std::vector<std::int64_t> connectivity(n), offsets(n);
  std::iota(connectivity.begin(), connectivity.end(), 0);
  std::iota(offsets.begin(), offsets.end(), 1);
  const std::vector<std::uint8_t> cell_types(n, 1);  // VTK_VERTEX

  const std::vector<AppendedArray> point_data = {
      {"velocity", "Float64", 3, raw_bytes(velocity)}, {"density", "Float64", 1, raw_bytes(f.density)},
      {"pressure", "Float64", 1, raw_bytes(f.pressure)}, {"kind", "UInt8", 1, raw_bytes(f.kind)},
      {"id", "UInt32", 1, raw_bytes(f.id)},
  };
  const AppendedArray points_array{"Points", "Float64", 3, raw_bytes(points)};
  const std::vector<AppendedArray> cell_arrays = {
      {"connectivity", "Int64", 1, raw_bytes(connectivity)},
      {"offsets", "Int64", 1, raw_bytes(offsets)},
      {"types", "UInt8", 1, raw_bytes(cell_types)},
  };

  std::string xml, appended;
  auto declare = [&](const AppendedArray& a) {
    // Scalars leave NumberOfComponents at its default of 1, so readers give them shape (N,), not (N, 1).
    const std::string components =
        a.components == 1 ? std::string() : fmt::format(R"( NumberOfComponents="{}")", a.components);
    xml += fmt::format(R"(        <DataArray type="{}" Name="{}"{} format="appended" offset="{}"/>)"
                       "\n",
                       a.type, a.name, components, appended.size());
    const std::uint64_t size = a.bytes.size();
    appended.append(reinterpret_cast<const char*>(&size), sizeof size);
    appended += a.bytes;
  };
  xml += "<?xml version=\"1.0\"?>\n";
  xml += "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  xml += "  <UnstructuredGrid>\n";
  xml += "    <FieldData>\n";
  xml += fmt::format("      <DataArray type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">{}</DataArray>\n",
                     f.time);
  xml += "    </FieldData>\n";
  xml += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  xml += "      <PointData Scalars=\"pressure\" Vectors=\"velocity\">\n";
  for (const auto& a : point_data) declare(a);
  xml += "      </PointData>\n      <Points>\n";
  declare(points_array);
  xml += "      </Points>\n      <Cells>\n";
  for (const auto& a : cell_arrays) declare(a);
  xml += "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n";
  xml += "  <AppendedData encoding=\"raw\">\n   _";
  xml += appended;
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  return xml;
}

std::string pvd_header() {
  return "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
}

std::string pvd_entry(double time, const std::string& file) {
  return fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", time, file);
}

std::string pvd_footer() { return "  </Collection>\n</VTKFile>\n"; }

std::string pvd_text(const std::vector<std::pair<double, std::string>>& entries) {
  std::string xml = pvd_header();
  for (const auto& [time, file] : entries) xml += pvd_entry(time, file);
  return xml + pvd_footer();
}

}  // namespace sluice
