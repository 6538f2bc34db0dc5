// Frames: the particle state at one output time, in particle-id order so that row k is the same
// particle in every frame. Written as NumPy .npz and as VTK XML (.vtu, listed in a .pvd).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sluice/simulation.hpp"

namespace sluice {

struct Frame {
  double time = 0.0;
  std::int64_t step = 0;
  double dx = 0.0;                  // particle spacing, for drawing particles at their size
  int dimension = 2;
  std::vector<double> position;     // N x dimension, row-major
  std::vector<double> velocity;     // N x dimension
  std::vector<double> density;
  std::vector<double> pressure;
  std::vector<std::uint8_t> kind;   // 0 fluid, 1 wall
  std::vector<std::uint32_t> id;

  [[nodiscard]] std::size_t size() const { return density.size(); }
};

Frame make_frame(const Simulation& sim);

// NumPy: arrays t, step, dx, x (N, dimension), v (N, dimension), rho, p, kind, id.
std::string frame_to_npz(const Frame& f);
Frame frame_from_npz(const std::string& bytes, const std::string& source);
Frame read_npz_frame(const std::filesystem::path& path);

// VTK XML UnstructuredGrid (.vtu) with raw appended binary data; one vertex cell per particle.
std::string frame_to_vtu(const Frame& f);

// A ParaView collection: (time, relative file name) per frame. The entries are lines between a fixed
// header and footer, so that a run can add them one by one (AppendFile).
std::string pvd_text(const std::vector<std::pair<double, std::string>>& entries);
std::string pvd_header();
std::string pvd_entry(double time, const std::string& file);
std::string pvd_footer();

}  // namespace sluice
