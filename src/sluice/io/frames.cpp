#include "sluice/io/frames.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <type_traits>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"

namespace sluice {

namespace {

// Not stored by the particles: the equation of state gives it from the density.
constexpr FieldSpec pressure_field{"pressure", "Pa", field_role::frame, "p"};

// The row of each particle in a frame: its place in increasing id order. That is the id itself
// unless particles have left an open tank (outflow), whose ids are then missing.
std::vector<std::uint32_t> id_rows(const std::vector<std::uint32_t>& id) {
  const std::size_t n = id.size();
  if (std::all_of(id.begin(), id.end(), [&](std::uint32_t k) { return k < n; })) return id;
  std::vector<std::uint32_t> by_id(n);
  std::iota(by_id.begin(), by_id.end(), 0u);
  std::sort(by_id.begin(), by_id.end(), [&](std::uint32_t a, std::uint32_t b) { return id[a] < id[b]; });
  std::vector<std::uint32_t> row(n);
  for (std::size_t k = 0; k < n; ++k) row[by_id[k]] = static_cast<std::uint32_t>(k);
  return row;
}

// A field's values placed at the particles' rows (id_rows); a Kind is stored as its byte.
template <class Field>
FrameField frame_field(const FieldSpec& spec, const Field& field, const std::vector<std::uint32_t>& row) {
  FrameField out{std::string(spec.name), std::string(spec.short_name), false, {}};
  using Element = typename Field::value_type;
  const std::size_t n = row.size();
  if constexpr (std::is_enum_v<Element>) {
    std::vector<std::underlying_type_t<Element>> rows(n);
    for (std::size_t i = 0; i < n; ++i) rows[row[i]] = static_cast<std::underlying_type_t<Element>>(field[i]);
    out.values = std::move(rows);
  } else if constexpr (std::is_arithmetic_v<Element>) {
    std::vector<Element> rows(n);
    for (std::size_t i = 0; i < n; ++i) rows[row[i]] = field[i];
    out.values = std::move(rows);
  } else {
    constexpr std::size_t dim = std::tuple_size_v<Field>;
    std::vector<typename Element::value_type> rows(dim * n);
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t d = 0; d < dim; ++d) rows[dim * row[i] + d] = field[d][i];
    out.vector = true;
    out.values = std::move(rows);
  }
  return out;
}

// The frame fields of particles in file order: the registry's fields with the frame role, and the
// pressure right after the density it is computed from.
template <int Dim>
std::vector<FrameField> frame_fields(const Particles<Dim>& p, const std::vector<double>& pressure) {
  std::vector<FrameField> fields;
  const std::vector<std::uint32_t> rows = id_rows(p.id);
  Particles<Dim>::fields(p, [&](const FieldSpec& spec, const auto& field) {
    if (!spec.has(field_role::frame)) return;
    fields.push_back(frame_field(spec, field, rows));
    if (spec.name == "density") fields.push_back(frame_field(pressure_field, pressure, rows));
  });
  return fields;
}

template <class T>
void read_values(const NpyArray& array, std::vector<T>& values) {
  values = array.values<T>();
}

// What render and analyze place, size and order the particles by: the time, the spacing and the
// positions. A run stops before it writes a state that is not finite (its instability guard), so a
// NaN or an infinity there is a damaged or foreign file, which would be drawn or measured silently
// wrong.
void check_finite(const Frame& f) {
  if (!std::isfinite(f.time)) throw FormatError(fmt::format("its time t = {} is not finite", f.time));
  if (!(f.dx > 0.0) || !std::isfinite(f.dx))
    throw FormatError(fmt::format("dx = {} is not a positive spacing", f.dx));
  const auto& x = f.position();
  const auto dim = static_cast<std::size_t>(f.dimension);
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i])) {
      const std::size_t row = i / dim;
      std::vector<double> at(x.begin() + static_cast<std::ptrdiff_t>(dim * row),
                             x.begin() + static_cast<std::ptrdiff_t>(dim * (row + 1)));
      throw FormatError(fmt::format("the position of particle id {} (row {} of x) is not finite: [{}]", f.id()[row],
                                    row, fmt::join(at, ", ")));
    }
}

}  // namespace

Frame::Frame() : fields(frame_fields(Particles<2>{}, {})) {}

std::size_t Frame::size() const {
  for (const FrameField& field : fields)
    if (!field.vector) return field.element_count();
  return 0;
}

namespace {

// A frame of the time now holding `particles` (a solver's, or all processes' gathered).
template <class Solver, class P>
void fill_frame(Frame& f, const Simulation& sim, const Solver& solver, const P& particles) {
  f.time = sim.time();
  f.step = sim.clock().step;
  f.dx = sim.config().dx;
  f.dimension = sim.dimension();
  std::vector<double> pressure(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) pressure[i] = solver.eos().pressure(particles.density[i]);
  f.fields = frame_fields(particles, pressure);
}

}  // namespace

Frame make_frame(const Simulation& sim) {
  Frame f;
  f.time = sim.time();
  f.step = sim.clock().step;
  f.dx = sim.config().dx;
  f.dimension = sim.dimension();
  // Every process's particles, on the root (the other processes' frames are empty).
  sim.visit([&](const auto& solver) {
    solver.with_all_particles([&](const auto& p) { fill_frame(f, sim, solver, p); });
  });
  return f;
}

Frame make_process_frame(const Simulation& sim) {
  Frame f;
  sim.visit([&](const auto& solver) { fill_frame(f, sim, solver, solver.particles()); });
  return f;
}

void write_frame_npz(const Frame& f, const ByteSink& out) {
  const std::size_t n = f.size();
  const std::vector<double> t{f.time}, dx{f.dx};
  const std::vector<std::int64_t> step{f.step};
  std::vector<std::pair<std::string, NpyView>> arrays = {
      {"t", NpyView::of(t, {})},
      {"step", NpyView::of(step, {})},
      {"dx", NpyView::of(dx, {})},
  };
  for (const FrameField& field : f.fields) {
    std::vector<std::size_t> shape{n};
    if (field.vector) shape.push_back(static_cast<std::size_t>(f.dimension));
    arrays.emplace_back(field.short_name,
                        std::visit([&](const auto& values) { return NpyView::of(values, shape); }, field.values));
  }
  write_npz(arrays, out);
}

std::string frame_to_npz(const Frame& f) {
  std::string bytes;
  write_frame_npz(f, [&](std::string_view b) { bytes += b; });
  return bytes;
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
    for (FrameField& field : f.fields) {
      // Frames written before bodies have no body array: each wall particle is the tank's.
      if (field.short_name == "body" && !arrays.contains("body")) continue;
      std::visit([&](auto& values) { read_values(array(field.short_name), values); }, field.values);
    }
    if (!arrays.contains("body")) {
      std::vector<std::uint8_t>& body = f.body();
      body.resize(f.kind().size());
      for (std::size_t i = 0; i < body.size(); ++i) body[i] = f.kind()[i] == 0 ? body_id::water : body_id::tank;
    }
    const auto& x_shape = array("x").shape;
    if (x_shape.size() != 2 || (x_shape[1] != 2 && x_shape[1] != 3))
      throw FormatError("'x' is not an array of 2D or 3D positions (N x 2 or N x 3)");
    f.dimension = static_cast<int>(x_shape[1]);
    const std::size_t n = x_shape[0];
    for (const FrameField& field : f.fields)
      if (field.element_count() != (field.vector ? x_shape[1] : 1) * n)
        throw FormatError("arrays have inconsistent lengths");
    check_finite(f);
    return f;
  } catch (const FormatError& e) {
    throw FormatError(fmt::format("{}: not a sluice frame: {}", source, e.what()));
  }
}

Frame read_npz_frame(const std::filesystem::path& path) {
  return frame_from_npz(read_file(path), path.string());
}

namespace {

// An array of the appended data block: its declaration, and how to write its bytes.
struct AppendedArray {
  std::string name;
  std::string type;  // VTK type name
  int components = 1;
  std::uint64_t bytes = 0;
  std::function<void(const ByteSink&)> write;
};

template <class T>
std::string vtk_type() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  else if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  else if constexpr (std::is_same_v<T, std::uint32_t>) return "UInt32";
  else {
    static_assert(std::is_same_v<T, std::uint8_t>, "a frame field of a type the .vtu writer does not name");
    return "UInt8";
  }
}

// Values made on the way out, a block at a time: value(i) for i < n, as `components` per value.
template <class T, class F>
void write_generated(const ByteSink& out, std::size_t n, F&& value) {
  constexpr std::size_t block = 4096;
  std::vector<T> buffer;
  buffer.reserve(block);
  for (std::size_t first = 0; first < n; first += block) {
    buffer.clear();
    for (std::size_t i = first; i < std::min(n, first + block); ++i) value(i, buffer);
    out(std::string_view(reinterpret_cast<const char*>(buffer.data()), buffer.size() * sizeof(T)));
  }
}

// A frame field as a VTK array; vectors get three components (VTK has no 2D points or vectors),
// padded on the way out.
AppendedArray vtk_array(const FrameField& field, std::size_t dimension) {
  return std::visit(
      [&](const auto& values) {
        using T = typename std::decay_t<decltype(values)>::value_type;
        if (!field.vector)
          return AppendedArray{field.name, vtk_type<T>(), 1, values.size() * sizeof(T), [&values](const ByteSink& out) {
                                 out(std::string_view(reinterpret_cast<const char*>(values.data()),
                                                      values.size() * sizeof(T)));
                               }};
        const std::size_t n = values.size() / dimension;
        return AppendedArray{field.name, vtk_type<T>(), 3, 3 * n * sizeof(T), [&values, n, dimension](const ByteSink& out) {
                               write_generated<T>(out, n, [&](std::size_t i, std::vector<T>& b) {
                                 for (std::size_t d = 0; d < 3; ++d) b.push_back(d < dimension ? values[dimension * i + d] : T{});
                               });
                             }};
      },
      field.values);
}

template <class T, class F>
AppendedArray generated_array(std::string name, std::size_t n, F value) {
  return AppendedArray{std::move(name), vtk_type<T>(), 1, n * sizeof(T), [n, value](const ByteSink& out) {
                         write_generated<T>(out, n, [&](std::size_t i, std::vector<T>& b) { b.push_back(value(i)); });
                       }};
}

}  // namespace

void write_frame_vtu(const Frame& f, const ByteSink& out) {
  const std::size_t n = f.size();
  AppendedArray points_array;
  std::vector<AppendedArray> point_data;
  for (const FrameField& field : f.fields) {
    AppendedArray a = vtk_array(field, static_cast<std::size_t>(f.dimension));
    if (field.name == "position") {  // the points of the grid; every other field is point data
      points_array = std::move(a);
      points_array.name = "Points";
    } else {
      point_data.push_back(std::move(a));
    }
  }
  // One vertex cell per particle.
  const std::vector<AppendedArray> cell_arrays = {
      generated_array<std::int64_t>("connectivity", n, [](std::size_t i) { return static_cast<std::int64_t>(i); }),
      generated_array<std::int64_t>("offsets", n, [](std::size_t i) { return static_cast<std::int64_t>(i + 1); }),
      generated_array<std::uint8_t>("types", n, [](std::size_t) { return std::uint8_t{1}; }),  // VTK_VERTEX
  };

  std::string xml;
  std::uint64_t offset = 0;
  auto declare = [&](const AppendedArray& a) {
    // Scalars leave NumberOfComponents at its default of 1, so readers give them shape (N,), not (N, 1).
    const std::string components =
        a.components == 1 ? std::string() : fmt::format(R"( NumberOfComponents="{}")", a.components);
    xml += fmt::format(R"(        <DataArray type="{}" Name="{}"{} format="appended" offset="{}"/>)"
                       "\n",
                       a.type, a.name, components, offset);
    offset += sizeof(std::uint64_t) + a.bytes;
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
  out(xml);
  // The appended block, in the order declared: each array's byte count, then its bytes.
  auto append = [&](const AppendedArray& a) {
    const std::uint64_t size = a.bytes;
    out(std::string_view(reinterpret_cast<const char*>(&size), sizeof size));
    a.write(out);
  };
  for (const auto& a : point_data) append(a);
  append(points_array);
  for (const auto& a : cell_arrays) append(a);
  out("\n  </AppendedData>\n</VTKFile>\n");
}

std::string frame_to_vtu(const Frame& f) {
  std::string bytes;
  write_frame_vtu(f, [&](std::string_view b) { bytes += b; });
  return bytes;
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
