// Frames: the particle state at one output time, in particle-id order so that row k is the same
// particle in every frame. Written as NumPy .npz and as VTK XML (.vtu, listed in a .pvd).
//
// A frame holds the particle fields with the frame role (Particles::fields), in registry order, and
// the pressure, which the particles do not store (the equation of state gives it from the density).
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "sluice/io/npz.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

// One per-particle array of a frame.
struct FrameField {
  std::string name;        // the registry's name; the array's name in .vtu files ("velocity")
  std::string short_name;  // the array's name in .npz files ("v")
  bool vector = false;     // N x dimension values (row-major), else N
  std::variant<std::vector<double>, std::vector<std::uint8_t>, std::vector<std::uint32_t>> values;

  [[nodiscard]] std::size_t element_count() const {
    return std::visit([](const auto& v) { return v.size(); }, values);
  }
};

struct Frame {
  Frame();  // every frame field, no particles

  double time = 0.0;
  std::int64_t step = 0;
  double dx = 0.0;  // particle spacing, for drawing particles at their size
  int dimension = 2;
  std::vector<FrameField> fields;  // in file order

  [[nodiscard]] std::size_t size() const;  // particles

  // The values of a field, by its .npz name; std::out_of_range if there is none of that type.
  template <class T>
  [[nodiscard]] const std::vector<T>& values(std::string_view short_name) const;
  template <class T>
  [[nodiscard]] std::vector<T>& values(std::string_view short_name) {
    return const_cast<std::vector<T>&>(std::as_const(*this).values<T>(short_name));
  }

  // The fields readers use: position and velocity N x dimension; kind 0 fluid, 1 wall.
  [[nodiscard]] const std::vector<double>& position() const { return values<double>("x"); }
  [[nodiscard]] const std::vector<double>& velocity() const { return values<double>("v"); }
  [[nodiscard]] const std::vector<double>& density() const { return values<double>("rho"); }
  [[nodiscard]] const std::vector<double>& pressure() const { return values<double>("p"); }
  [[nodiscard]] const std::vector<std::uint8_t>& kind() const { return values<std::uint8_t>("kind"); }
  [[nodiscard]] const std::vector<std::uint32_t>& id() const { return values<std::uint32_t>("id"); }
  // The body of each particle (core/particles.hpp, body_id: 0 water, 1 the tank, k + 2 wall k).
  [[nodiscard]] const std::vector<std::uint8_t>& body() const { return values<std::uint8_t>("body"); }
  std::vector<double>& position() { return values<double>("x"); }
  std::vector<double>& velocity() { return values<double>("v"); }
  std::vector<double>& density() { return values<double>("rho"); }
  std::vector<double>& pressure() { return values<double>("p"); }
  std::vector<std::uint8_t>& kind() { return values<std::uint8_t>("kind"); }
  std::vector<std::uint32_t>& id() { return values<std::uint32_t>("id"); }
  std::vector<std::uint8_t>& body() { return values<std::uint8_t>("body"); }
};

template <class T>
const std::vector<T>& Frame::values(std::string_view short_name) const {
  for (const FrameField& field : fields)
    if (field.short_name == short_name)
      if (const auto* v = std::get_if<std::vector<T>>(&field.values)) return *v;
  throw std::out_of_range("a frame has no field '" + std::string(short_name) + "' of that type");
}

// Every process's particles, on the root process (the others' frames are empty). Collective.
Frame make_frame(const Simulation& sim);
// This process's particles alone, in id order (all of them with one process).
Frame make_process_frame(const Simulation& sim);

// NumPy: arrays t, step, dx, then each field under its short name: x (N, dimension), v (N, dimension),
// rho, p, kind, id.
// write_frame_npz streams the file to `out` without copying the frame's arrays; frame_to_npz returns it.
void write_frame_npz(const Frame& f, const ByteSink& out);
std::string frame_to_npz(const Frame& f);
// A frame read back: FormatError "<source>: not a sluice frame: ..." if an array is missing or
// malformed, or the time, dx or a position is not finite (dx not positive).
Frame frame_from_npz(const std::string& bytes, const std::string& source);
Frame read_npz_frame(const std::filesystem::path& path);

// VTK XML UnstructuredGrid (.vtu) with raw appended binary data; one vertex cell per particle, the
// position as the points and the other fields as point data (vectors with three components).
// write_frame_vtu streams it, padding the vectors a block at a time; frame_to_vtu returns it.
void write_frame_vtu(const Frame& f, const ByteSink& out);
std::string frame_to_vtu(const Frame& f);

// A ParaView collection: (time, relative file name) per frame. The entries are lines between a fixed
// header and footer, so that a run can add them one by one (AppendFile).
std::string pvd_text(const std::vector<std::pair<double, std::string>>& entries);
std::string pvd_header();
std::string pvd_entry(double time, const std::string& file);
std::string pvd_footer();

}  // namespace sluice
