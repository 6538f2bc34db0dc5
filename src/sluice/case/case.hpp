// A case: everything that defines a run, as plain data. Filled from a TOML file by the loader
// (case/load.hpp); the solver reads it and knows nothing of files.
//
// Vectors have three components; a 2D case uses the first two (the third is 0). The up axis is the
// last one: y in 2D, z in 3D.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "sluice/core/vec.hpp"
#include "sluice/geometry/motion.hpp"
#include "sluice/geometry/triangle_mesh.hpp"

namespace sluice {

using Vec3 = Vec<3>;

// The choices a case makes, as types. The names are the case file's spellings, in enum order.
enum class KernelType { cubic_spline, wendland_c2 };
inline constexpr std::array<std::string_view, 2> kernel_type_names = {"cubic_spline", "wendland_c2"};

enum class WallBoundary { dynamic, adami, mdbc };
inline constexpr std::array<std::string_view, 3> wall_boundary_names = {"dynamic", "adami", "mdbc"};
enum class WallSlip { no_slip, free_slip };
inline constexpr std::array<std::string_view, 2> wall_slip_names = {"no_slip", "free_slip"};
// automatic: the log-law wall function where validation chose it, none elsewhere (wall_friction_in_effect).
enum class WallFriction { none, log_law, automatic };
inline constexpr std::array<std::string_view, 3> wall_friction_names = {"none", "log_law", "auto"};
enum class DiffusionGradient { hydrostatic, renormalised };
inline constexpr std::array<std::string_view, 2> diffusion_gradient_names = {"hydrostatic", "renormalised"};

enum class Precision { double_, single };
inline constexpr std::array<std::string_view, 2> precision_names = {"double", "single"};
enum class Integrator { predictor_corrector, euler, leapfrog };
inline constexpr std::array<std::string_view, 3> integrator_names = {"predictor_corrector", "euler", "leapfrog"};

enum class Shape { box, polygon, mesh };
inline constexpr std::array<std::string_view, 3> shape_names = {"box", "polygon", "mesh"};

enum class ProbeType { pressure, gauge, front };
inline constexpr std::array<std::string_view, 3> probe_type_names = {"pressure", "gauge", "front"};
enum class ProbeCorrection { shepard, linear };
inline constexpr std::array<std::string_view, 2> probe_correction_names = {"shepard", "linear"};
enum class GaugeMeasure { highest, column, surface };
inline constexpr std::array<std::string_view, 3> gauge_measure_names = {"highest", "column", "surface"};

// A wall's prescribed motion: a law for its translation and one for its rotation (geometry/motion.hpp).
enum class MotionLawType { none, linear, polynomial, sinusoidal, file, wave, absorber };
inline constexpr std::array<std::string_view, 7> motion_law_names = {"none", "linear", "polynomial", "sinusoidal",
                                                                      "file", "wave",   "absorber"};
enum class AfterMotion { hold, continue_ };
inline constexpr std::array<std::string_view, 2> after_motion_names = {"hold", "continue"};
enum class PastFileEnd { error, hold };
inline constexpr std::array<std::string_view, 2> past_file_end_names = {"error", "hold"};
// A wave law's waves: regular (one height and period) or irregular from a JONSWAP spectrum.
enum class WaveSpectrum { regular, jonswap };
inline constexpr std::array<std::string_view, 2> wave_spectrum_names = {"regular", "jonswap"};

template <class E, std::size_t N>
constexpr std::string_view name_of(E value, const std::array<std::string_view, N>& names) {
  return names[static_cast<std::size_t>(value)];
}

// One law of a wall's motion: [wall.translation] (a displacement in m along `direction`) or
// [wall.rotation] (an angle in degrees about `axis` through `centre`). Values, rates and coefficients
// are in the law's unit: m, m/s for a translation; degrees, degrees/s for a rotation.
struct MotionLawSpec {
  MotionLawType law = MotionLawType::none;
  Vec3 direction{};             // translation: the direction of motion (normalised when read)
  Vec3 centre{};                // rotation: the centre of rotation at the start
  Vec3 axis{0.0, 0.0, 1.0};     // rotation, 3D: the axis (normalised when read); 2D turns about z
  double speed = 0.0;           // linear: the rate
  double start = 0.0;           // linear, polynomial, sinusoidal: when the law starts
  double end = 0.0;             // linear, polynomial: when it ends
  std::vector<double> coefficients;  // polynomial: c0, c1, ... of sum c_k (t - start)^k
  AfterMotion after = AfterMotion::hold;  // polynomial: after `end`
  double amplitude = 0.0, period = 0.0, phase = 0.0, ramp = 0.0;  // sinusoidal (phase in degrees)
  std::string file;             // file: a CSV of the motion; made absolute when read
  std::string time_column, column;
  double scale = 1.0, time_offset = 0.0;
  PastFileEnd past_end = PastFileEnd::error;
  // wave: a piston making regular waves of `height` and `period` on water `depth` deep, first or
  // second order (Madsen), its stroke times `gain`, ramped over `ramp` periods from `start`.
  double height = 0.0, depth = 0.0, gain = 1.0;
  int order = 1;
  // wave, spectrum = jonswap: irregular waves of significant height Hs and peak period Tp from a
  // JONSWAP spectrum of peak enhancement gamma, in `components` components whose phases come from
  // `seed` (geometry/wave_theory.hpp), ramped over `ramp` peak periods; depth, gain, start as above.
  WaveSpectrum spectrum = WaveSpectrum::regular;
  double significant_height = 0.0, peak_period = 0.0, gamma = 3.3;
  int components = 200, seed = 1;
  // Active absorption (a piston: law = "wave" with absorb = true, or law = "absorber", which only
  // absorbs): the piston's velocity corrected by sqrt(g/depth) times the difference between the
  // surface measured in front of it and the target's, the correction drawn back over
  // `absorption_time` (0: 4 periods, or 20 sqrt(depth/g) for an absorber) and held within
  // +-`absorption_limit` (0: the target's half-stroke, or depth/4 for an absorber).
  bool absorb = false;
  double absorption_time = 0.0, absorption_limit = 0.0;
  std::shared_ptr<const MotionSeries> series;  // file: the series read (set by the loader, not a key)
};

// A floating wall ([wall.floating]): a rigid body moved by the water's force on its particles, gravity,
// a constant external force and moment, and linear springs and dampers on its degrees of freedom
// (solver/floating.hpp). The degrees of freedom are, in order, x, y (and z) for the centre of
// gravity's motion, then the rotations (rz in 2D; rx, ry, rz in 3D); per-degree vectors (stiffness,
// damping, anchor) have one value for each, in that order. Rotations are in degrees where the case
// gives an angle or angular velocity, and their stiffness and damping per radian.
struct FloatingSpec {
  double mass = 0.0;                       // kg (kg per metre of depth in 2D); or
  double density = 0.0;                    // kg/m^3: mass = density x the shape's volume (area in 2D)
  std::vector<double> centre_of_gravity;   // m; empty: the shape's centroid
  std::vector<double> inertia;             // kg m^2 about the centre of gravity: 2D [Izz]; 3D [Ixx, Iyy, Izz] or with [.., Ixy, Ixz, Iyz]
  std::vector<double> radius_of_gyration;  // m, in place of the inertia: 2D [k]; 3D [kx, ky, kz]
  Vec3 velocity{};                         // m/s, of the centre of gravity at the start
  std::vector<double> angular_velocity;    // deg/s at the start: 2D [wz]; 3D [wx, wy, wz]; empty: at rest
  std::vector<std::string> lock;           // degrees of freedom held at their start value (x, y, z, rx, ry, rz)
  std::vector<double> stiffness;           // per degree of freedom: N/m (N m/rad); empty: none
  std::vector<double> damping;             // per degree of freedom: N s/m (N m s/rad); empty: none
  std::vector<double> anchor;              // per degree of freedom: where its spring is at rest (m, deg)
  Vec3 force{};                            // N: a constant external force (a weight added, a tow)
  std::vector<double> moment;              // N m about the centre of gravity: 2D [Mz]; 3D [Mx, My, Mz]
  double friction = 0.0;                   // Coulomb friction coefficient of its contacts with other solids
};

// The names of the degrees of freedom of a floating body, in the order of its per-degree vectors.
inline std::vector<std::string> floating_dofs(int dimension) {
  if (dimension == 2) return {"x", "y", "rz"};
  return {"x", "y", "z", "rx", "ry", "rz"};
}

// A water region or a solid wall: a box (min, max), in 2D a polygon (its points, in either order), in
// 3D a closed triangle mesh read from a file (STL or OBJ), scaled and moved. A wall is a body: it has a
// name and may move (its translation and rotation laws; both none: fixed).
struct Region {
  Shape shape = Shape::box;
  Vec3 min{};
  Vec3 max{};
  std::vector<Vec2> points;  // polygon vertices, implicitly closed
  std::string file;          // mesh file; made absolute once read from disk (see case/meshes.hpp)
  double scale = 1.0;        // mesh vertex v is placed at scale * v + offset
  Vec3 offset{};
  std::shared_ptr<const TriangleMesh> mesh;  // the placed, checked mesh (set by the loader, not a key)
  // Walls only.
  std::string name;                   // unique among the walls; default "wall<N>", N from 1
  MotionLawSpec translation, rotation;
  bool floats = false;   // a [wall.floating] table: moved by the water, not by laws
  FloatingSpec floating;
  [[nodiscard]] bool moves() const {
    return translation.law != MotionLawType::none || rotation.law != MotionLawType::none || floats;
  }
};

// A probe sampled during the run (see io/probes.hpp).
struct Probe {
  std::string name;
  ProbeType type = ProbeType::pressure;
  Vec3 point{};        // pressure: where; gauge: where the vertical line stands; front: origin of the search
  Vec3 direction{};    // front: direction along which the furthest particle is found
  double band = 0.0;   // gauge: half-width of the band around the line (0 = one particle spacing)
  double size = 0.0;   // pressure: the sensor's diameter (0 = a point); it lies on the nearest wall surface
  ProbeCorrection correction = ProbeCorrection::shepard;  // pressure: how the interpolation is corrected
  GaugeMeasure measure = GaugeMeasure::highest;           // gauge: the highest fluid, the column's top, or the kernel's surface
  double interval = 0.0;  // sampling interval in simulated time (0 = every step)
  std::string wall;       // the [[wall]] the probe moves with (its name); empty: fixed in space
};

struct Case {
  // [case]
  std::string name;
  std::string description;

  // [domain]
  int dimension = 2;
  double dx = 0.0;          // particle spacing
  double h_over_dx = 0.0;   // smoothing length h = h_over_dx * dx
  KernelType kernel = KernelType::cubic_spline;
  Precision pair_precision = Precision::double_;  // of the pair arithmetic; the state is always double

  // [tank]: the inner walls are x = 0, x = width, the floor at up = 0 and (with a lid) up = height;
  // in 3D also y = 0 and y = depth.
  double tank_width = 0.0;
  double tank_depth = 0.0;  // 3D only
  double tank_height = 0.0;
  bool tank_lid = true;

  // [fluid]
  double rest_density = 0.0;
  double sound_speed = 0.0;
  double gamma = 0.0;
  double viscosity = 0.0;   // dynamic viscosity mu

  // [physics]
  Vec3 gravity{};
  double artificial_viscosity = 0.0;  // Monaghan alpha
  double artificial_pressure = 0.0;   // Monaghan (2000) epsilon; 0 = off
  int artificial_pressure_exponent = 4;
  double density_diffusion = 0.0;     // delta-SPH delta
  DiffusionGradient diffusion_gradient = DiffusionGradient::hydrostatic;  // physics/density_gradient.hpp
  int shepard_every = 0;              // steps between Shepard density filters (0 = off)
  bool hydrostatic_start = true;
  bool hydrostatic_squeeze = false;  // and the water squeezed to its hydrostatic density (geometry/setup.cpp)
  double initial_pressure = 0.0;      // added to the water's initial pressure
  WallBoundary wall_boundary = WallBoundary::dynamic;
  WallSlip wall_slip = WallSlip::free_slip;  // mdbc walls
  WallFriction wall_friction = WallFriction::none;  // physics/wall_friction.hpp; see wall_friction_in_effect
  bool wall_tension = true;  // negative pressures act between water and wall particles (false: counted as 0)
  bool wall_no_penetration = true;   // water within dx/4 of a wall loses its velocity into it (geometry/leaks.hpp)
  double shifting = 0.0;                // particle shifting coefficient A; 0 = off
  double free_surface_threshold = 0.0;  // div r below which a fluid particle is on the free surface

  // [tank.translation], [tank.rotation]: the tank's own walls move as these laws say (a moving tank).
  MotionLawSpec tank_translation, tank_rotation;
  [[nodiscard]] bool tank_moves() const {
    return tank_translation.law != MotionLawType::none || tank_rotation.law != MotionLawType::none;
  }

  // [damping]: a zone where the water's velocity is relaxed (an absorbing end of a wave flume): from
  // the plane through damping_start normal to damping_direction, over damping_length, the velocity
  // decays at the rate damping_strength s^2 (s from 0 to 1 across the zone, 1 beyond it).
  double damping_length = 0.0;  // 0: no zone
  Vec3 damping_start{};
  Vec3 damping_direction{1.0, 0.0, 0.0};
  double damping_strength = 10.0;
  [[nodiscard]] bool damps() const { return damping_length > 0.0; }

  // [release]: the first water region held behind a gate lifted at gate_speed (case/release_gate.hpp)
  bool release_gate = false;
  double gate_speed = 1.0;  // m/s

  // [time]
  double end_time = 0.0;
  Integrator integrator = Integrator::predictor_corrector;
  double cfl = 0.0;
  double fixed_dt = 0.0;    // 0 = adaptive

  // [output]
  double output_interval = 0.0;
  std::vector<std::string> output_formats;  // of "vtk", "npz"
  double checkpoint_interval = 0.0;         // 0 = only at the end
  int max_frames = 10000;                   // a run planning more frames is refused (a mistyped interval)
  double checkpoint_wall_interval = 20.0;   // wall-clock seconds between checkpoints while running; 0 = none
  double bodies_interval = 0.0;             // simulated time between rows of bodies/<name>.csv; 0 = every step

  std::vector<Region> water;
  std::vector<Region> walls;
  // Where relative mesh file names are looked up: the case file's directory; empty for built-in cases
  // and stored cases (the meshes shipped in cases/, then the current directory). Not a key.
  std::string mesh_directory;
  std::vector<Probe> probes;

  [[nodiscard]] double smoothing_length() const { return h_over_dx * dx; }
  // Inner size of the tank along each axis (the first `dimension` entries): width, (depth,) height.
  [[nodiscard]] Vec3 tank_size() const {
    return dimension == 3 ? Vec3{tank_width, tank_depth, tank_height} : Vec3{tank_width, tank_height, 0.0};
  }
  [[nodiscard]] bool writes(std::string_view format) const {
    for (const auto& f : output_formats)
      if (f == format) return true;
    return false;
  }
};

// Calls f(law, key, rotation) for every motion law of the case, the tank's first ("tank.translation",
// "tank.rotation"), then each wall's ("wall[0].translation", ...): for the checks and file loading that
// treat them alike.
template <class C, class F>
void for_each_motion_law(C& c, F&& f) {
  f(c.tank_translation, std::string("tank.translation"), false);
  f(c.tank_rotation, std::string("tank.rotation"), true);
  for (std::size_t i = 0; i < c.walls.size(); ++i) {
    f(c.walls[i].translation, "wall[" + std::to_string(i) + "].translation", false);
    f(c.walls[i].rotation, "wall[" + std::to_string(i) + "].rotation", true);
  }
}

// The first Dim components of a case vector.
template <int Dim>
Vec<Dim> first(const Vec3& v) {
  Vec<Dim> out{};
  for (int d = 0; d < Dim; ++d) out[d] = v[d];
  return out;
}

// The wall friction a case runs. "auto" is the log-law wall function on mdbc walls with free slip in
// 2D, the combination validation chose for wall pressures (docs/validation.md, "Defaults"), and none
// on other walls: dynamic and no-slip walls have a friction of their own, adami walls were not
// validated with it, and neither was 3D; none without a viscosity, which the wall function needs. Resolved when the solver starts, not when the case is read,
// so that `--set physics.wall_boundary=dynamic` on a case that leaves the friction to "auto" works.
inline WallFriction wall_friction_in_effect(const Case& c) {
  if (c.wall_friction != WallFriction::automatic) return c.wall_friction;
  return c.dimension == 2 && c.wall_boundary == WallBoundary::mdbc && c.wall_slip == WallSlip::free_slip &&
                 c.viscosity > 0.0
             ? WallFriction::log_law
             : WallFriction::none;
}

}  // namespace sluice
