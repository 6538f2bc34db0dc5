#include "sluice/case/parameter_table.hpp"

#include <fmt/format.h>

#include <array>
#include <string_view>

namespace sluice {

namespace {

constexpr double unbounded_lower = 1.0;
constexpr double unbounded_upper = -1.0;

template <class Owner, class T>
Param<Owner> declare(std::string key, T Owner::*field, std::string unit, ParamValue def, double lower, double upper,
                     std::string description, std::vector<std::string> choices = {}) {
  return Param<Owner>{std::move(key), field,  std::move(unit),    std::move(def),
                      lower,          upper,  std::move(choices), std::move(description)};
}

template <class T>
struct member_of;
template <class O, class T>
struct member_of<T O::*> {
  using owner = O;
  using type = T;
};

// An enum field, written in the case file as one of `names` (in enum order).
template <auto Member, std::size_t N>
auto declare_choice(std::string key, typename member_of<decltype(Member)>::type def,
                    const std::array<std::string_view, N>& names, std::string description) {
  using Owner = typename member_of<decltype(Member)>::owner;
  using E = typename member_of<decltype(Member)>::type;
  const ChoiceField<Owner> field{+[](const Owner& o) { return static_cast<int>(o.*Member); },
                                 +[](Owner& o, int i) { o.*Member = static_cast<E>(i); }};
  return Param<Owner>{std::move(key),
                      field,
                      "",
                      std::string(names[static_cast<std::size_t>(def)]),
                      unbounded_lower,
                      unbounded_upper,
                      std::vector<std::string>(names.begin(), names.end()),
                      std::move(description)};
}

// Marks on a declaration, written around it in the tables below.
template <class Owner>
Param<Owner> with_3d_default(ParamValue def, Param<Owner> p) {
  p.default_3d = std::move(def);
  return p;
}

template <class Owner>
Param<Owner> only_in_3d(Param<Owner> p) {
  p.only_3d = true;
  return p;
}

template <class Owner>
Param<Owner> required(Param<Owner> p) {
  p.default_value = std::monostate{};
  return p;
}

template <class Owner>
Param<Owner> used_by(bool (*applies)(const Owner&), Param<Owner> p) {
  p.applies = applies;
  return p;
}

// A key that only the items of `applies` use, which they may leave out.
template <class Owner>
Param<Owner> optional_for(bool (*applies)(const Owner&), Param<Owner> p) {
  p.applies = applies;
  p.optional = true;
  return p;
}

bool is_box(const Region& r) { return r.shape == Shape::box; }
bool is_polygon(const Region& r) { return r.shape == Shape::polygon; }
bool is_mesh(const Region& r) { return r.shape == Shape::mesh; }

}  // namespace

const std::vector<Section>& case_sections() {
  static const std::vector<Section> sections = {
      {"case", "What this case is.", false},
      {"domain", "Discretisation.", false},
      {"tank", "The closed box tank: inner walls at x = 0 and x = width (and in 3D y = 0 and y = depth), the floor at up = 0 and (with a lid) the top at up = height; up is y in 2D, z in 3D. The tank is fixed unless [tank.translation] or [tank.rotation] gives it a motion law (as a [[wall]]'s): then its walls move by the law and carry the water (a rolling or shaken tank).", false},
      {"fluid", "Fluid properties and the weakly-compressible equation of state.", false},
      {"physics", "Forces and stabilisation.", false},
      {"damping", "A zone that absorbs waves: the water's velocity relaxed with a strength growing quadratically across it (the far end of a wave flume).", false},
      {"release", "How the water is released: at once (the default), or from behind a gate lifted as in a laboratory.", false},
      {"time", "Time integration.", false},
      {"output", "What is written, and how often.", false},
      {"water", "Regions filled with water at rest. Repeat [[water]] for each region; overlaps are merged.", true},
      {"wall", "Solid obstacles inside the tank (walls of the tank itself come from [tank]). Repeat [[wall]] per obstacle; each is filled with wall particles to a depth of 2h inside its outline.", true},
      {"probe", "Time series sampled during the run and written to probes/<name>.csv. Repeat [[probe]] per probe.", true},
  };
  return sections;
}

const std::vector<Param<Case>>& case_params() {
  constexpr double inf = 1e300;
  static const std::vector<Param<Case>> params = {
      declare("case.name", &Case::name, "", std::string("unnamed"), unbounded_lower, unbounded_upper,
              "Name of the case; the default output folder is out/<name>."),
      declare("case.description", &Case::description, "", std::string(""), unbounded_lower, unbounded_upper,
              "One line saying what the case is."),
      declare("domain.dimension", &Case::dimension, "", 2, 2.0, 3.0,
              "Space dimensions: 2 (x, y; y up) or 3 (x, y, z; z up). Vectors have this many components."),
      declare("domain.dx", &Case::dx, "m", 0.2, 1e-4, 100.0, "Particle spacing (dx); particle mass is rho0 * dx^2 (dx^3 in 3D)."),
      with_3d_default(1.3, declare("domain.h_over_dx", &Case::h_over_dx, "", 2.0, 1.0, 3.0,
                                   "Smoothing length in particle spacings: h = h_over_dx * dx. The kernel support "
                                   "is 2h. The defaults are what validation chose: 2 in 2D, with mdbc walls and "
                                   "shifting; 1.3 in 3D, where h = 2 dx costs 3.6 times the pairs (see "
                                   "docs/validation.md, \"Defaults\").")),
      declare_choice<&Case::kernel>("domain.kernel", KernelType::cubic_spline, kernel_type_names, "Smoothing kernel."),
      declare_choice<&Case::pair_precision>(
              "domain.pair_precision", Precision::double_, precision_names,
              "Arithmetic of the particle pairs (the forces and density rates): double, or single (twice the "
              "vector lanes, about 1.5-2x faster; positions, velocities, densities and each particle's sums stay "
              "double; see docs/speed.md, \"Single-precision pairs\", for its effect on the validation numbers)."),
      declare("tank.width", &Case::tank_width, "m", 20.0, 1e-3, 1e5, "Inner width of the tank (along x)."),
      only_in_3d(declare("tank.depth", &Case::tank_depth, "m", 10.0, 1e-3, 1e5,
                         "Inner depth of the tank (along y; 3D only).")),
      declare("tank.height", &Case::tank_height, "m", 10.0, 1e-3, 1e5,
              "Inner height of the tank (along the up axis: y in 2D, z in 3D)."),
      declare("tank.lid", &Case::tank_lid, "", true, unbounded_lower, unbounded_upper,
              "Close the tank with a wall at the top (up = height). Without it, water that goes over the walls "
              "and beyond their reach is removed and counted (outflow in diagnostics.csv)."),
      declare("fluid.density", &Case::rest_density, "kg/m^3", 1000.0, 1.0, 1e5, "Rest density rho0."),
      declare("fluid.sound_speed", &Case::sound_speed, "m/s", 20.0, 1e-2, 1e5,
              "Numerical speed of sound c0; keep it >= 10x the largest flow speed for density changes near 1%."),
      declare("fluid.gamma", &Case::gamma, "", 7.0, 1.0, 10.0, "Tait exponent gamma: P = B((rho/rho0)^gamma - 1), B = rho0 c0^2/gamma."),
      declare("fluid.viscosity", &Case::viscosity, "Pa s", 0.001, 0.0, 1e6, "Dynamic viscosity mu (water: 0.001)."),
      with_3d_default(Vec3{0.0, 0.0, -9.81},
                      declare("physics.gravity", &Case::gravity, "m/s^2", Vec3{0.0, -9.81, 0.0}, unbounded_lower,
                              unbounded_upper, "Gravitational acceleration [gx, gy] in 2D, [gx, gy, gz] in 3D.")),
      declare("physics.artificial_viscosity", &Case::artificial_viscosity, "", 0.1, 0.0, 1.0,
              "Monaghan (1992) artificial viscosity alpha (0 = off)."),
      declare("physics.artificial_pressure", &Case::artificial_pressure, "", 0.0, 0.0, 1.0,
              "Monaghan (2000) artificial pressure epsilon against particle clumping (tensile instability): a "
              "short-range repulsion eps |P|/rho^2 where P < 0 (and 0.01 P/rho^2 where P > 0); 0 = off, 0.2 is "
              "Monaghan's value."),
      declare("physics.artificial_pressure_exponent", &Case::artificial_pressure_exponent, "", 4, 1.0, 12.0,
              "Exponent n of the artificial pressure's kernel ratio (W(r)/W(dx))^n."),
      declare("physics.density_diffusion", &Case::density_diffusion, "", 0.1, 0.0, 1.0,
              "delta-SPH density diffusion coefficient delta (Molteni & Colagrossi 2009, hydrostatic part removed as in Fourtakas et al. 2019; 0 = off)."),
      declare_choice<&Case::diffusion_gradient>(
              "physics.density_diffusion_gradient", DiffusionGradient::hydrostatic, diffusion_gradient_names,
              "The density gradient the density diffusion leaves alone: hydrostatic (rho g / c^2, Fourtakas et al. "
              "2019) or renormalised (each fluid particle's own, a first-order corrected sum over its fluid "
              "neighbours: the full delta-SPH of Antuono et al. 2010 and Marrone et al. 2011; a second pass over the "
              "pairs). See docs/physics.md, \"Density diffusion\"."),
      declare("physics.shepard_every", &Case::shepard_every, "steps", 20, 0.0, 1e9,
              "Re-initialise the fluid density with a Shepard filter every this many steps (0 = off)."),
      declare("physics.initial_pressure", &Case::initial_pressure, "Pa", 0.0, -1e9, 1e9,
              "Pressure added to the water's initial (hydrostatic) pressure; negative puts the water under tension "
              "(see the tension case)."),
      declare("physics.hydrostatic_start", &Case::hydrostatic_start, "", true, unbounded_lower, unbounded_upper,
              "Start water (and the walls under it) at hydrostatic density, so water at rest stays at rest."),
      declare("physics.hydrostatic_squeeze", &Case::hydrostatic_squeeze, "", false, unbounded_lower, unbounded_upper,
              "With hydrostatic_start: also squeeze each column of water onto its bottom to the spacing of its "
              "density, so that m / rho is each particle's volume and still water's pressure gradient is rho g "
              "instead of about 2 % steeper (see docs/physics.md, \"The initial state\"); it stirs the water beside the side walls."),
      declare_choice<&Case::wall_boundary>(
              "physics.wall_boundary", WallBoundary::mdbc, wall_boundary_names,
              "Wall treatment: dynamic (wall particles' density evolves by the continuity equation like the fluid's) "
              "or adami (Adami, Hu & Adams 2012: wall pressure extrapolated from the fluid before each force "
              "evaluation, hydrostatic term included, negative values clamped to 0; free slip: no artificial "
              "viscosity between fluid and wall) or mdbc (English et al. 2022: wall density from a first-order fit to the "
              "water at each wall particle's mirror image through the wall surface, held at rho0 or above; the "
              "default: the best wall pressures validation measured, see docs/validation.md, \"Defaults\")."),
      declare_choice<&Case::wall_slip>(
              "physics.wall_slip", WallSlip::free_slip, wall_slip_names,
              "For mdbc walls: free_slip (the wall particles take the tangential part of the water's velocity at their "
              "mirror image and minus its normal part) or no_slip (minus all of it, so the velocity vanishes at the "
              "surface; with the artificial viscosity this is a strong wall friction: see docs/physics.md, \"Walls\")."),
      declare_choice<&Case::wall_friction>(
              "physics.wall_friction", WallFriction::automatic, wall_friction_names,
              "Wall friction for walls that have none of their own (mdbc with free_slip, adami): none, or log_law "
              "(the shear stress of the law of the wall for a smooth wall, from each water particle's speed along "
              "the wall and its distance to it, with fluid.viscosity; spread over the first 2h of water: see "
              "docs/physics.md, \"Wall friction\"), or auto (the default): log_law on mdbc walls with free slip in "
              "2D, the combination validation chose, and none on other walls and in 3D."),
      declare("physics.wall_tension", &Case::wall_tension, "", true, unbounded_lower, unbounded_upper,
              "Whether a wall holds the water beside it in tension: true, the pressure force between a water and a "
              "wall particle takes both pressures as they are; false, a negative pressure counts as 0 there, so a "
              "wall never pulls water towards itself (lets mdbc walls run the beach and obstacle cases: see docs/physics.md, \"Walls\")."),
      declare("physics.wall_no_penetration", &Case::wall_no_penetration, "", true, unbounded_lower, unbounded_upper,
              "Whether water closer than dx/4 to a wall surface loses its velocity into the wall before each move: "
              "stopped at the surface, reflected a quarter spacing inside, untouched from dx/4 out (water at rest "
              "sits at dx/2). Keeps fast water, and shifted water, out of every kind of wall; false lets the walls' "
              "pressure alone hold the water (what leaks in is put back and counted): see docs/physics.md, \"Walls\"."),
      with_3d_default(0.0, declare("physics.shifting", &Case::shifting, "", 2.0, 0.0, 10.0,
              "Particle shifting coefficient A (0 = off): each step moves every fluid particle by "
              "-A h |v| dt grad C (Lind et al. 2012, Skillen et al. 2013, with the anti-clumping weight of Sun et al. "
              "2017), along the surface only near a free surface. 2 is DualSPHysics's value and the default in 2D, "
              "as validated; 0 in 3D.")),
      with_3d_default(2.5, declare("physics.free_surface_threshold", &Case::free_surface_threshold, "", 1.5, 0.5, 3.0,
                                   "For particle shifting: a fluid particle whose position divergence div r (about 2 "
                                   "inside the water in 2D, 3 in 3D) is below this is on the free surface.")),
      declare("damping.length", &Case::damping_length, "m", 0.0, 0.0, inf,
              "The length of the damping zone, along damping.direction from damping.start; 0: none. In it the "
              "water's velocity decays as exp(-strength s^2 dt) each step, s growing from 0 at its start to 1 at "
              "its end (and 1 beyond): waves running into it are absorbed rather than reflected."),
      declare("damping.start", &Case::damping_start, "m", Vec3{}, unbounded_lower, unbounded_upper,
              "A point on the plane where the damping zone starts."),
      declare("damping.direction", &Case::damping_direction, "", Vec3{1.0, 0.0, 0.0}, unbounded_lower,
              unbounded_upper, "The direction into the zone from its start (normalised), e.g. [1, 0] for the far "
              "end of a flume along +x."),
      declare("damping.strength", &Case::damping_strength, "1/s", 10.0, 0.0, inf,
              "The relaxation rate at the zone's end (1/s)."),
      declare("release.gate", &Case::release_gate, "", false, unbounded_lower, unbounded_upper,
              "Hold the first [[water]] region (a box) behind a gate at its face towards +x: a plate 4 dx thick "
              "across the tank, from the floor to 4 dx above the water, lifted at release.gate_speed from t = 0 "
              "until its foot is dx above the water and held there (a moving [[wall]] named gate). false: the "
              "water is released at once."),
      declare("release.gate_speed", &Case::gate_speed, "m/s", 1.0, 1e-6, inf,
              "The speed at which the gate of release.gate rises."),
      declare("time.end", &Case::end_time, "s", 30.0, 0.0, inf, "Simulated end time."),
      declare_choice<&Case::integrator>(
              "time.integrator", Integrator::predictor_corrector, integrator_names,
              "Time integrator: predictor-corrector (midpoint, two force evaluations per step), forward Euler "
              "(one) or leapfrog (kick-drift-kick velocity Verlet, one: the rates of a step's end carry into the "
              "next step; see docs/physics.md, \"Time integration\")."),
      declare("time.cfl", &Case::cfl, "", 0.2, 0.1, 0.3,
              "Courant number C_CFL: dt = C_CFL * min(h/|v_ij|max, sqrt(h/|a|max), h/c_max). Forward Euler amplifies "
              "sound waves: use 0.1 with it (the predictor-corrector and the leapfrog are stable at 0.2)."),
      declare("time.dt", &Case::fixed_dt, "s", 0.0, 0.0, inf, "Fixed time step; 0 = adaptive (recommended)."),
      declare("output.interval", &Case::output_interval, "s", 0.1, 1e-9, inf, "Simulated time between frames."),
      declare("output.formats", &Case::output_formats, "", std::vector<std::string>{"vtk", "npz"}, unbounded_lower,
              unbounded_upper, "Frame formats: vtk (ParaView .vtu + .pvd) and npz (NumPy).", {"vtk", "npz"}),
      declare("output.checkpoint_interval", &Case::checkpoint_interval, "s", 0.0, 0.0, inf,
              "Simulated time between checkpoints; 0 = only at the end (and on Ctrl-C)."),
      declare("output.max_frames", &Case::max_frames, "", 10000, 1.0, 1e9,
              "The most frames a run may plan to write (time.end / output.interval): a run planning more is "
              "refused before it starts, so that a mistyped interval does not fill the disk. Raise it to write more."),
      declare("output.checkpoint_wall_interval", &Case::checkpoint_wall_interval, "s", 20.0, 0.0, inf,
              "Wall-clock time between the checkpoints a run writes as it goes (each replaces the last), so that a "
              "run that is killed can be restarted from at most this long ago; 0 = none. Stretched to 50 times "
              "the time a checkpoint takes to write, so that they cost at most 2 % of the run."),
      declare("output.bodies_interval", &Case::bodies_interval, "s", 0.0, 0.0, inf,
              "Simulated time between the rows of bodies/<name>.csv, the series of each moving wall (its "
              "position, angle, velocity, and the force and moment of the water on it); 0 = every step."),
  };
  return params;
}

const std::vector<Param<Region>>& region_params() {
  static const std::vector<Param<Region>> params = {
      declare_choice<&Region::shape>("shape", Shape::box, shape_names,
                                     "Shape of the region: a box (min, max), in 2D a polygon (points), in 3D a "
                                     "closed triangle mesh read from a file (file, scale, offset)."),
      used_by(is_box, declare("min", &Region::min, "m", Vec3{}, unbounded_lower, unbounded_upper,
                              "Box: lower corner [x, y] (2D) or [x, y, z] (3D).")),
      used_by(is_box, declare("max", &Region::max, "m", Vec3{}, unbounded_lower, unbounded_upper,
                              "Box: upper corner [x, y] (2D) or [x, y, z] (3D).")),
      used_by(is_polygon,
              declare("points", &Region::points, "m", std::vector<Vec2>{}, unbounded_lower, unbounded_upper,
                      "Polygon (2D): its corners [[x, y], ...] in order around it (at least 3; closed automatically).")),
      used_by(is_mesh,
              declare("file", &Region::file, "", std::string(""), unbounded_lower, unbounded_upper,
                      "Mesh (3D): an STL (ASCII or binary) or OBJ file of a closed triangle surface, its normals "
                      "outwards; a relative path is relative to the case file's directory; the meshes of the sources' "
                      "cases/ directory are built in and found by that relative name (\"meshes/cylinder.stl\").")),
      optional_for(is_mesh, declare("scale", &Region::scale, "", 1.0, 1e-9, 1e9,
                                    "Mesh: factor on the file's coordinates (0.001 for a file in millimetres).")),
      optional_for(is_mesh, declare("offset", &Region::offset, "m", Vec3{}, unbounded_lower, unbounded_upper,
                                    "Mesh: moves it after scaling; vertex v is placed at scale * v + offset.")),
  };
  return params;
}

const std::vector<Param<Region>>& wall_params() {
  static const std::vector<Param<Region>> params = [] {
    std::vector<Param<Region>> p = region_params();
    p.insert(p.begin(), declare("name", &Region::name, "", std::string(""), unbounded_lower, unbounded_upper,
                                "Name of the wall, a body: letters, digits, '_', '-' and '.', unique among the walls; "
                                "its series go to bodies/<name>.csv. Empty: wall1, wall2, ... in file order."));
    return p;
  }();
  return params;
}

namespace {

bool law_is(const MotionLawSpec& m, MotionLawType t) { return m.law == t; }
bool moves(const MotionLawSpec& m) { return m.law != MotionLawType::none; }
bool is_linear(const MotionLawSpec& m) { return law_is(m, MotionLawType::linear); }
bool is_polynomial(const MotionLawSpec& m) { return law_is(m, MotionLawType::polynomial); }
bool is_sinusoidal(const MotionLawSpec& m) { return law_is(m, MotionLawType::sinusoidal); }
bool is_file(const MotionLawSpec& m) { return law_is(m, MotionLawType::file); }
bool is_wave(const MotionLawSpec& m) { return law_is(m, MotionLawType::wave); }
bool is_regular_wave(const MotionLawSpec& m) { return is_wave(m) && m.spectrum == WaveSpectrum::regular; }
bool is_jonswap(const MotionLawSpec& m) { return is_wave(m) && m.spectrum == WaveSpectrum::jonswap; }
bool is_periodic(const MotionLawSpec& m) { return is_sinusoidal(m) || is_wave(m); }
bool is_absorber(const MotionLawSpec& m) { return law_is(m, MotionLawType::absorber); }
bool needs_depth(const MotionLawSpec& m) { return is_wave(m) || is_absorber(m); }
bool absorbs(const MotionLawSpec& m) { return is_absorber(m) || (is_wave(m) && m.absorb); }
bool has_period(const MotionLawSpec& m) { return is_sinusoidal(m) || is_regular_wave(m); }
bool has_interval(const MotionLawSpec& m) { return is_linear(m) || is_polynomial(m); }
bool has_start(const MotionLawSpec& m) { return has_interval(m) || is_periodic(m); }

std::vector<Param<MotionLawSpec>> law_params(bool rotation) {
  constexpr double inf = 1e300;
  const std::string unit = rotation ? "deg" : "m", rate = rotation ? "deg/s" : "m/s";
  const std::string what = rotation ? "angle" : "displacement";
  std::vector<Param<MotionLawSpec>> p = {
      declare_choice<&MotionLawSpec::law>(
          "law", MotionLawType::none, motion_law_names,
          fmt::format("The law of the wall's {}: none; linear (a constant rate between start and end); polynomial "
                      "(sum of c_k (t - start)^k between start and end, then held or continued); sinusoidal (amplitude "
                      "sin(2 pi (t - start)/period + phase) - amplitude sin(phase), ramped up over `ramp` periods); "
                      "file (a recorded series, interpolated by a natural cubic spline); wave (regular waves of `height` "
                      "and `period` on water `depth` deep, the stroke S from Biesel's transfer function: a translation "
                      "is a piston, with Madsen's second-order correction for order = 2; a rotation is a flap hinged "
                      "at `centre` (its height above the floor), its angle -atan(X / (depth - hinge)) for the "
                      "displacement X = (S/2) sin(omega t) at the still-water level, so that its top swings first "
                      "along up x axis: towards +x in 2D); with spectrum = \"jonswap\", irregular waves: the sum "
                      "of such motions for the components of a JONSWAP spectrum); absorber (a piston at rest that "
                      "absorbs the waves arriving at it by active absorption: a translation only).",
                      what)),
  };
  if (rotation) {
    p.push_back(used_by(moves, declare("centre", &MotionLawSpec::centre, "m", Vec3{}, unbounded_lower, unbounded_upper,
                                       "The centre of rotation at the start; it moves with the wall's translation.")));
    p.push_back(optional_for(moves, only_in_3d(declare("axis", &MotionLawSpec::axis, "", Vec3{0.0, 0.0, 1.0},
                                                       unbounded_lower, unbounded_upper,
                                                       "The axis of rotation (3D; right-handed; normalised). In 2D "
                                                       "the wall turns about z, anticlockwise for positive angles."))));
  } else {
    p.push_back(used_by(moves, declare("direction", &MotionLawSpec::direction, "", Vec3{}, unbounded_lower,
                                       unbounded_upper, "The direction of the translation (normalised).")));
  }
  const std::vector<Param<MotionLawSpec>> rest = {
      used_by(is_linear, declare("speed", &MotionLawSpec::speed, rate, 0.0, unbounded_lower, unbounded_upper,
                                 "Linear: the rate.")),
      optional_for(has_start, declare("start", &MotionLawSpec::start, "s", 0.0, 0.0, inf,
                                      "When the law starts; before it the wall is at rest where it starts.")),
      used_by(has_interval, declare("end", &MotionLawSpec::end, "s", 0.0, 0.0, inf, "When the law ends.")),
      used_by(is_polynomial, declare("coefficients", &MotionLawSpec::coefficients, unit, std::vector<double>{},
                                     unbounded_lower, unbounded_upper,
                                     "Polynomial: c0, c1, c2, ... of sum c_k (t - start)^k (units " + unit + ", " +
                                         unit + "/s, " + unit + "/s^2, ...).")),
      optional_for(is_polynomial, declare_choice<&MotionLawSpec::after>(
                                      "after", AfterMotion::hold, after_motion_names,
                                      "Polynomial, after `end`: hold (stop where it got to) or continue (at the "
                                      "rate it had at `end`).")),
      used_by(is_sinusoidal, declare("amplitude", &MotionLawSpec::amplitude, unit, 0.0, unbounded_lower,
                                     unbounded_upper, "Sinusoidal: the amplitude.")),
      used_by(has_period, declare("period", &MotionLawSpec::period, "s", 0.0, 1e-6, inf,
                                  "Sinusoidal, wave (regular): the period.")),
      optional_for(is_sinusoidal, declare("phase", &MotionLawSpec::phase, "deg", 0.0, -360.0, 360.0,
                                          "Sinusoidal: the phase; the value is shifted so that it starts at 0.")),
      optional_for(is_periodic, declare("ramp", &MotionLawSpec::ramp, "periods", 0.0, 0.0, 1e6,
                                        "Sinusoidal, wave: the number of periods (for spectrum = \"jonswap\", of "
                                        "the peak period, at least 1) over which the motion grows from rest ((1 - cos) "
                                        "ramp: the wall starts with zero velocity and acceleration).")),
      used_by(is_regular_wave, declare("height", &MotionLawSpec::height, "m", 0.0, 1e-9, inf,
                                       "Wave (regular): the height H (crest to trough) of the waves the wave maker "
                                       "makes.")),
      used_by(needs_depth, declare("depth", &MotionLawSpec::depth, "m", 0.0, 1e-9, inf,
                                   "Wave, absorber: the still water's depth h at the wave maker or absorber, which the theory "
                                   "needs.")),
      optional_for(is_wave, declare("order", &MotionLawSpec::order, "", 1, 1, 2,
                                    "Wave: 1, the first-order motion (S/2) sin(omega t); 2 (a piston), with Madsen's "
                                    "(1971) second-order term at 2 omega, which cancels the free second harmonic the "
                                    "first-order motion makes.")),
      optional_for(is_wave, declare("gain", &MotionLawSpec::gain, "", 1.0, 0.0, inf,
                                    "Wave: a factor on the wave maker's motion (the stroke theory gives times gain).")),
      optional_for(is_wave, declare_choice<&MotionLawSpec::spectrum>(
                                "spectrum", WaveSpectrum::regular, wave_spectrum_names,
                                "Wave: regular (waves of one `height` and `period`) or jonswap (irregular waves from "
                                "a JONSWAP spectrum: significant_height, peak_period, gamma, components, seed; first "
                                "order, each component's stroke from its own transfer function; see docs/waves.md).")),
      used_by(is_jonswap, declare("significant_height", &MotionLawSpec::significant_height, "m", 0.0, 1e-9, inf,
                                  "Wave (jonswap): the significant height Hs = 4 sqrt(m0) of the spectrum the wave "
                                  "maker makes.")),
      used_by(is_jonswap, declare("peak_period", &MotionLawSpec::peak_period, "s", 0.0, 1e-6, inf,
                                  "Wave (jonswap): the spectrum's peak period Tp = 1/fp.")),
      optional_for(is_jonswap, declare("gamma", &MotionLawSpec::gamma, "", 3.3, 1.0, 10.0,
                                       "Wave (jonswap): the peak enhancement factor gamma (1: a Pierson-Moskowitz "
                                       "spectrum; 3.3: the JONSWAP mean).")),
      optional_for(is_jonswap, declare("components", &MotionLawSpec::components, "", 200, 1.0, 10000.0,
                                       "Wave (jonswap): the number of components, in equal bins of width fp/M, "
                                       "M = round(components/2.5), from fp/2 to about 3 fp; the waves repeat every "
                                       "M peak periods.")),
      optional_for(is_jonswap, declare("seed", &MotionLawSpec::seed, "", 1, 0.0, 2147483647.0,
                                       "Wave (jonswap): the seed of the components' random phases (the same seed "
                                       "makes the same waves on every machine).")),
      optional_for(is_wave, declare("absorb", &MotionLawSpec::absorb, "", false, unbounded_lower, unbounded_upper,
                                    "Wave, a piston (translation): active absorption, the piston's velocity corrected "
                                    "by -sqrt(g/h) times the difference between the surface measured in front of "
                                    "it and the target wave's there, so that waves coming back to it are not "
                                    "reflected again (docs/waves.md).")),
      optional_for(absorbs, declare("absorption_time", &MotionLawSpec::absorption_time, "s", 0.0, 0.0, inf,
                                    "Absorbing piston: the time over which the correction's mean is removed and the "
                                    "piston drawn back to its target (0: 4 periods, 4 peak periods, or 20 "
                                    "sqrt(h/g) for an absorber alone).")),
      optional_for(absorbs, declare("absorption_limit", &MotionLawSpec::absorption_limit, "m", 0.0, 0.0, inf,
                                    "Absorbing piston: the largest correction of its displacement (0: half the "
                                    "target's stroke, or h/4 for an absorber alone); the tank must leave it room.")),
      used_by(is_file, declare("file", &MotionLawSpec::file, "", std::string(""), unbounded_lower, unbounded_upper,
                               "File: a CSV with a header line; a relative path is relative to the case file's "
                               "directory.")),
      used_by(is_file, declare("time_column", &MotionLawSpec::time_column, "", std::string(""), unbounded_lower,
                               unbounded_upper, "File: the name of the time column (s), as the header spells it.")),
      used_by(is_file, declare("column", &MotionLawSpec::column, "", std::string(""), unbounded_lower, unbounded_upper,
                               "File: the name of the column of the " + what + ", as the header spells it.")),
      optional_for(is_file, declare("scale", &MotionLawSpec::scale, "", 1.0, unbounded_lower, unbounded_upper,
                                    "File: the factor from the column's values to the wall's " + what + " in " + unit +
                                        " (a lever arm's ratio, a unit's)." )),
      optional_for(is_file, declare("time_offset", &MotionLawSpec::time_offset, "s", 0.0, unbounded_lower,
                                    unbounded_upper, "File: added to the file's times (the run's t = file time + offset).")),
      optional_for(is_file, declare_choice<&MotionLawSpec::past_end>(
                                "past_end", PastFileEnd::error, past_file_end_names,
                                "File: a run whose end time is past the file's last time is refused (error) or the "
                                "wall stays at its last value at rest (hold).")),
  };
  p.insert(p.end(), rest.begin(), rest.end());
  return p;
}

}  // namespace

const std::vector<Param<MotionLawSpec>>& motion_law_params(bool rotation) {
  static const std::vector<Param<MotionLawSpec>> translation = law_params(false), turning = law_params(true);
  return rotation ? turning : translation;
}

const std::vector<Param<FloatingSpec>>& floating_params() {
  constexpr double inf = 1e300;
  using F = FloatingSpec;
  const std::vector<double> none;
  static const std::vector<Param<F>> params = {
      declare("mass", &F::mass, "kg", 0.0, 0.0, inf,
              "The body's mass (in 2D per metre of depth, kg/m); 0: from `density`. Give one of mass and density."),
      declare("density", &F::density, "kg/m^3", 0.0, 0.0, inf,
              "The body's mean density: its mass is this times the shape's volume (area in 2D); 0: `mass` is given."),
      declare("centre_of_gravity", &F::centre_of_gravity, "m", none, unbounded_lower, unbounded_upper,
              "Where the centre of gravity is at the start, [x, y] (2D) or [x, y, z]; empty: the shape's centroid "
              "(a body of uniform density)."),
      declare("inertia", &F::inertia, "kg m^2", none, unbounded_lower, unbounded_upper,
              "Moment of inertia about the centre of gravity: [Izz] in 2D (kg m^2 per metre of depth), [Ixx, Iyy, "
              "Izz] or [Ixx, Iyy, Izz, Ixy, Ixz, Iyz] in 3D (the tensor's entries, axes of the case); empty: from "
              "radius_of_gyration, else from the shape at uniform density."),
      declare("radius_of_gyration", &F::radius_of_gyration, "m", none, unbounded_lower, unbounded_upper,
              "Radius of gyration about the centre of gravity, in place of the inertia (I = mass k^2): [k] in 2D, "
              "[kx, ky, kz] in 3D."),
      declare("velocity", &F::velocity, "m/s", Vec3{}, unbounded_lower, unbounded_upper,
              "Velocity of the centre of gravity at the start."),
      declare("angular_velocity", &F::angular_velocity, "deg/s", none, unbounded_lower, unbounded_upper,
              "Angular velocity at the start: [wz] in 2D, [wx, wy, wz] in 3D; empty: none."),
      declare("lock", &F::lock, "", std::vector<std::string>{}, unbounded_lower, unbounded_upper,
              "Degrees of freedom held at their start: any of x, y, rz in 2D (x, y, z, rx, ry, rz in 3D), where "
              "x, y, z move the centre of gravity and rx, ry, rz turn about axes through it. [\"x\", \"rz\"]: "
              "heave only in 2D.",
              {"x", "y", "z", "rx", "ry", "rz"}),
      declare("stiffness", &F::stiffness, "N/m, N m/rad", none, unbounded_lower, unbounded_upper,
              "Linear springs to fixed points, one per degree of freedom in the order x, y, (z,) (rx, ry,) rz: "
              "force -stiffness (q - anchor) (in 2D per metre of depth); empty or 0: none. A rotation's spring "
              "acts on the angle (radians) about its axis."),
      declare("damping", &F::damping, "N s/m, N m s/rad", none, unbounded_lower, unbounded_upper,
              "Linear dampers, one per degree of freedom in the same order: force -damping dq/dt; empty or 0: none."),
      declare("anchor", &F::anchor, "m, deg", none, unbounded_lower, unbounded_upper,
              "Where each spring is at rest, one value per degree of freedom in the same order: the centre of "
              "gravity's coordinate (m) or the angle (deg). Needed with a stiffness."),
      declare("force", &F::force, "N", Vec3{}, unbounded_lower, unbounded_upper,
              "A constant external force on the centre of gravity (a weight added, a tow), besides gravity."),
      declare("moment", &F::moment, "N m", none, unbounded_lower, unbounded_upper,
              "A constant external moment about the centre of gravity: [Mz] in 2D, [Mx, My, Mz] in 3D; empty: none."),
      declare("friction", &F::friction, "", 0.0, 0.0, 10.0,
              "Coulomb friction coefficient of the body's contacts with the tank, other walls and other floating "
              "bodies (the tangential force at most this times the normal one); 0: frictionless."),
  };
  return params;
}

const std::vector<Param<Probe>>& probe_params() {
  static const std::vector<Param<Probe>> params = {
      declare("name", &Probe::name, "", std::monostate{}, unbounded_lower, unbounded_upper,
              "Name of the probe; its series goes to probes/<name>.csv."),
      // A probe must say what it measures: its type has no default.
      required(declare_choice<&Probe::type>("type", ProbeType::pressure, probe_type_names,
                                            "pressure: kernel-interpolated pressure at `point` (see size, correction); gauge: water "
                                            "height on the vertical line through `point`; front: furthest fluid "
                                            "particle from `point` along `direction`.")),
      declare("point", &Probe::point, "m", std::monostate{}, unbounded_lower, unbounded_upper,
              "Location [x, y] (2D) or [x, y, z] (3D)."),
      declare("direction", &Probe::direction, "", Vec3{1.0, 0.0, 0.0}, unbounded_lower, unbounded_upper,
              "Direction of a front probe."),
      declare("band", &Probe::band, "m", 0.0, 0.0, 1e300,
              "Half-width of a gauge's band of particles around its vertical line (in x, and in y in 3D); 0 = one "
              "particle spacing."),
      declare("size", &Probe::size, "m", 0.0, 0.0, 1e300,
              "Diameter of a pressure sensor; 0 = a point. A sensor lies on the wall surface nearest to `point` "
              "(a segment across the wall in 2D, a disc in 3D) and reads the mean of the interpolated pressure over "
              "it, 0 where no water is."),
      declare_choice<&Probe::correction>(
              "correction", ProbeCorrection::shepard, probe_correction_names,
              "How a pressure probe interpolates: shepard (kernel average normalised by its weights) or linear "
              "(first-order: the value at the point of the weighted least-squares linear fit of the neighbours' "
              "pressures, which reaches a wall's surface; Shepard where the neighbours are too few or in a line)."),
      declare_choice<&Probe::measure>(
              "measure", GaugeMeasure::highest, gauge_measure_names,
              "What a gauge reads: highest (the top of the highest fluid particle in its band) or column (the top "
              "of the water standing on the line's foot, `point`: spray and drops above a gap of more than one "
              "particle spacing are not water level, as for a wire gauge) or surface (the highest point of the line "
              "where the kernel's water fraction sum V_j W_j reaches 1/2, between samples dx/8 apart: the surface "
              "of the smoothed water, not of a particle, which a wave gauge wants)."),
      declare("interval", &Probe::interval, "s", 0.0, 0.0, 1e300, "Sampling interval; 0 = every step."),
      declare("wall", &Probe::wall, "", std::string(""), unbounded_lower, unbounded_upper,
              "The name of the [[wall]] the probe moves with, or \"tank\" in a case whose tank moves: `point` is "
              "where it is at the start, and it is carried by that wall's motion (a pressure sensor on a rolling "
              "tank's side, a gauge on a moving body); a gauge's line stays vertical and a front's direction "
              "fixed. Empty: fixed in space."),
  };
  return params;
}

std::vector<std::string> all_keys() {
  std::vector<std::string> keys;
  for (const auto& p : case_params()) keys.push_back(p.key);
  for (const auto& p : region_params()) keys.push_back("water." + p.key);
  for (const auto& p : wall_params()) keys.push_back("wall." + p.key);
  for (const char* owner : {"tank", "wall"})
    for (const bool rotation : {false, true})
      for (const auto& p : motion_law_params(rotation))
        keys.push_back(fmt::format("{}.{}.{}", owner, rotation ? "rotation" : "translation", p.key));
  for (const auto& p : floating_params()) keys.push_back("wall.floating." + p.key);
  for (const auto& p : probe_params()) keys.push_back("probe." + p.key);
  return keys;
}

}  // namespace sluice
