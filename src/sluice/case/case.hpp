// A case: everything that defines a run, as plain data. Filled from a TOML file by the loader
// (case/params.hpp); the solver reads it and knows nothing of files.
#pragma once

#include <string>
#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

// A water region or a solid wall: a box (min, max) or a polygon (its points, in either order).
struct Region {
  std::string shape;         // "box" | "polygon"
  Vec2 min{};
  Vec2 max{};
  std::vector<Vec2> points;  // polygon vertices, implicitly closed
};

// A probe sampled during the run (see io/probes.hpp).
struct Probe {
  std::string name;
  std::string type;    // "pressure" | "gauge" | "front"
  Vec2 point{};        // pressure: where; gauge: x of the gauge (point[0]) ; front: origin of the search
  Vec2 direction{};    // front: direction along which the furthest particle is found
  double band = 0.0;   // gauge: half-width of the band in x (0 = one particle spacing)
  double interval = 0.0;  // sampling interval in simulated time (0 = every step)
};

struct Case {
  // [case]
  std::string name;
  std::string description;

  // [domain]
  double dx = 0.0;          // particle spacing
  double h_over_dx = 0.0;   // smoothing length h = h_over_dx * dx
  std::string kernel;       // "cubic_spline" | "wendland_c2"

  // [tank]: the inner walls are x = 0, x = width, y = 0 and (with a lid) y = height.
  double tank_width = 0.0;
  double tank_height = 0.0;
  bool tank_lid = true;

  // [fluid]
  double rest_density = 0.0;
  double sound_speed = 0.0;
  double gamma = 0.0;
  double viscosity = 0.0;   // dynamic viscosity mu

  // [physics]
  Vec2 gravity{};
  double artificial_viscosity = 0.0;  // Monaghan alpha
  double artificial_pressure = 0.0;   // Monaghan (2000) epsilon; 0 = off
  int artificial_pressure_exponent = 4;
  double density_diffusion = 0.0;     // delta-SPH delta
  int shepard_every = 0;              // steps between Shepard density filters (0 = off)
  bool hydrostatic_start = true;
  double initial_pressure = 0.0;      // added to the water's initial pressure
  std::string wall_boundary;          // "dynamic" | "adami"

  // [time]
  double end_time = 0.0;
  std::string integrator;   // "euler" | "predictor_corrector"
  double cfl = 0.0;
  double fixed_dt = 0.0;    // 0 = adaptive

  // [output]
  double output_interval = 0.0;
  std::vector<std::string> output_formats;  // of "vtk", "npz"
  double checkpoint_interval = 0.0;         // 0 = only at the end

  std::vector<Region> water;
  std::vector<Region> walls;
  std::vector<Probe> probes;

  [[nodiscard]] double smoothing_length() const { return h_over_dx * dx; }
};

}  // namespace sluice
