// The moving walls' series: bodies/<name>.csv for each wall with a motion law, a row per sample with
// the body's reference point (its centre of rotation, moved with it), its angle about its axis
// (degrees), their rates, and the force and moment the water exerts on it (Solver::body_load). A
// floating body's row has its centre of gravity, its orientation (the angle in 2D; the quaternion
// and roll, pitch and yaw in 3D), its velocities, the water's force and moment about the centre of
// gravity that moved it, its springs' and dampers' forces and moments, and its contacts'.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sluice/io/append_file.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

// The header of a body's series in `dimension` dimensions.
std::string body_header(int dimension);
std::string floating_body_header(int dimension);

class BodyRecorder {
 public:
  // As ProbeRecorder: rows on disk after `keep_until` are dropped (a restart continues from there);
  // with several processes every process samples and only the root (`writes`) touches the files.
  // `interval`: output.bodies_interval (0 = every step).
  BodyRecorder(const Simulation& sim, const std::filesystem::path& dir, double interval, double keep_until, bool fresh,
               bool writes = true);
  void sample(const Simulation& sim);  // called after every step; collective
  void flush();
  void sync();

 private:
  struct Series {
    std::uint8_t body;
    AppendFile file;
    std::string rows;
  };
  std::vector<Series> series_;
  double interval_ = 0.0;
  std::int64_t next_sample_ = 0;
  bool writes_ = true;
};

}  // namespace sluice
