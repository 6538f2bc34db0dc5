#include "sluice/case/params.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#define TOML_EXCEPTIONS 1
#include <toml++/toml.h>

namespace sluice {

namespace detail {
struct BuiltinCaseText {
  const char* name;
  const char* text;
};
extern const BuiltinCaseText builtin_case_texts[];
extern const std::size_t builtin_case_count;
}  // namespace detail

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

}  // namespace

const std::vector<Section>& case_sections() {
  static const std::vector<Section> sections = {
      {"case", "What this case is.", false},
      {"domain", "Discretisation.", false},
      {"tank", "The closed box tank: inner walls at x = 0 and x = width (and in 3D y = 0 and y = depth), the floor at up = 0 and (with a lid) the top at up = height; up is y in 2D, z in 3D.", false},
      {"fluid", "Fluid properties and the weakly-compressible equation of state.", false},
      {"physics", "Forces and stabilisation.", false},
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
  static const std::vector<Param<Case>> params = [] {
    std::vector<Param<Case>> v = {
      declare("case.name", &Case::name, "", std::string("unnamed"), unbounded_lower, unbounded_upper,
              "Name of the case; the default output folder is out/<name>."),
      declare("case.description", &Case::description, "", std::string(""), unbounded_lower, unbounded_upper,
              "One line saying what the case is."),
      declare("domain.dimension", &Case::dimension, "", 2, 2.0, 3.0,
              "Space dimensions: 2 (x, y; y up) or 3 (x, y, z; z up). Vectors have this many components."),
      declare("domain.dx", &Case::dx, "m", 0.2, 1e-4, 100.0, "Particle spacing (dx); particle mass is rho0 * dx^2 (dx^3 in 3D)."),
      declare("domain.h_over_dx", &Case::h_over_dx, "", 1.3, 1.0, 3.0,
              "Smoothing length in particle spacings: h = h_over_dx * dx. The kernel support is 2h."),
      declare_choice<&Case::kernel>("domain.kernel", KernelType::cubic_spline, kernel_type_names, "Smoothing kernel."),
      declare("tank.width", &Case::tank_width, "m", 20.0, 1e-3, 1e5, "Inner width of the tank (along x)."),
      declare("tank.depth", &Case::tank_depth, "m", 10.0, 1e-3, 1e5, "Inner depth of the tank (along y; 3D only)."),
      declare("tank.height", &Case::tank_height, "m", 10.0, 1e-3, 1e5,
              "Inner height of the tank (along the up axis: y in 2D, z in 3D)."),
      declare("tank.lid", &Case::tank_lid, "", true, unbounded_lower, unbounded_upper,
              "Close the tank with a wall at the top (up = height)."),
      declare("fluid.density", &Case::rest_density, "kg/m^3", 1000.0, 1.0, 1e5, "Rest density rho0."),
      declare("fluid.sound_speed", &Case::sound_speed, "m/s", 20.0, 1e-2, 1e5,
              "Numerical speed of sound c0; keep it >= 10x the largest flow speed for density changes near 1%."),
      declare("fluid.gamma", &Case::gamma, "", 7.0, 1.0, 10.0, "Tait exponent gamma: P = B((rho/rho0)^gamma - 1), B = rho0 c0^2/gamma."),
      declare("fluid.viscosity", &Case::viscosity, "Pa s", 0.001, 0.0, 1e6, "Dynamic viscosity mu (water: 0.001)."),
      declare("physics.gravity", &Case::gravity, "m/s^2", Vec3{0.0, -9.81, 0.0}, unbounded_lower, unbounded_upper,
              "Gravitational acceleration [gx, gy] in 2D, [gx, gy, gz] in 3D."),
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
      declare("physics.shepard_every", &Case::shepard_every, "steps", 20, 0.0, 1e9,
              "Re-initialise the fluid density with a Shepard filter every this many steps (0 = off)."),
      declare("physics.initial_pressure", &Case::initial_pressure, "Pa", 0.0, -1e9, 1e9,
              "Pressure added to the water's initial (hydrostatic) pressure; negative puts the water under tension "
              "(see the tension case)."),
      declare("physics.hydrostatic_start", &Case::hydrostatic_start, "", true, unbounded_lower, unbounded_upper,
              "Start water (and the walls under it) at hydrostatic density, so water at rest stays at rest."),
      declare_choice<&Case::wall_boundary>(
              "physics.wall_boundary", WallBoundary::dynamic, wall_boundary_names,
              "Wall treatment: dynamic (wall particles' density evolves by the continuity equation like the fluid's) "
              "or adami (Adami, Hu & Adams 2012: wall pressure extrapolated from the fluid before each force "
              "evaluation, hydrostatic term included, negative values clamped to 0; free slip: no artificial "
              "viscosity between fluid and wall)."),
      declare("time.end", &Case::end_time, "s", 30.0, 0.0, inf, "Simulated end time."),
      declare_choice<&Case::integrator>(
              "time.integrator", Integrator::predictor_corrector, integrator_names,
              "Time integrator: forward Euler (one force evaluation per step) or predictor-corrector (two)."),
      declare("time.cfl", &Case::cfl, "", 0.2, 0.1, 0.3,
              "Courant number C_CFL: dt = C_CFL * min(h/|v_ij|max, sqrt(h/|a|max), h/c_max). Forward Euler amplifies "
              "sound waves: use 0.1 with it."),
      declare("time.dt", &Case::fixed_dt, "s", 0.0, 0.0, inf, "Fixed time step; 0 = adaptive (recommended)."),
      declare("output.interval", &Case::output_interval, "s", 0.1, 1e-9, inf, "Simulated time between frames."),
      declare("output.formats", &Case::output_formats, "", std::vector<std::string>{"vtk", "npz"}, unbounded_lower,
              unbounded_upper, "Frame formats: vtk (ParaView .vtu + .pvd) and npz (NumPy).", {"vtk", "npz"}),
      declare("output.checkpoint_interval", &Case::checkpoint_interval, "s", 0.0, 0.0, inf,
              "Simulated time between checkpoints; 0 = only at the end (and on Ctrl-C)."),
    };
    for (auto& p : v) {
      if (p.key == "physics.gravity") p.default_3d = Vec3{0.0, 0.0, -9.81};
      if (p.key == "tank.depth") p.only_3d = true;
    }
    return v;
  }();
  return params;
}

const std::vector<Param<Region>>& region_params() {
  static const std::vector<Param<Region>> params = [] {
    auto is_box = +[](const Region& r) { return r.shape == Shape::box; };
    auto is_polygon = +[](const Region& r) { return r.shape == Shape::polygon; };
    std::vector<Param<Region>> v = {
        declare_choice<&Region::shape>("shape", Shape::box, shape_names,
                                       "Shape of the region: a box (min, max) or, in 2D, a polygon (points)."),
        declare("min", &Region::min, "m", Vec3{}, unbounded_lower, unbounded_upper,
                "Box: lower corner [x, y] (2D) or [x, y, z] (3D)."),
        declare("max", &Region::max, "m", Vec3{}, unbounded_lower, unbounded_upper,
                "Box: upper corner [x, y] (2D) or [x, y, z] (3D)."),
        declare("points", &Region::points, "m", std::vector<Vec2>{}, unbounded_lower, unbounded_upper,
                "Polygon (2D): its corners [[x, y], ...] in order around it (at least 3; closed automatically)."),
    };
    v[1].applies = is_box;
    v[2].applies = is_box;
    v[3].applies = is_polygon;
    return v;
  }();
  return params;
}

const std::vector<Param<Probe>>& probe_params() {
  static const std::vector<Param<Probe>> params = [] {
    std::vector<Param<Probe>> v = {
      declare("name", &Probe::name, "", std::monostate{}, unbounded_lower, unbounded_upper,
              "Name of the probe; its series goes to probes/<name>.csv."),
      declare_choice<&Probe::type>("type", ProbeType::pressure, probe_type_names,
                                   "pressure: kernel-weighted fluid pressure at `point`; gauge: water height on the "
                                   "vertical line through `point`; front: furthest fluid particle from `point` along "
                                   "`direction`."),
      declare("point", &Probe::point, "m", std::monostate{}, unbounded_lower, unbounded_upper,
              "Location [x, y] (2D) or [x, y, z] (3D)."),
      declare("direction", &Probe::direction, "", Vec3{1.0, 0.0, 0.0}, unbounded_lower, unbounded_upper,
              "Direction of a front probe."),
      declare("band", &Probe::band, "m", 0.0, 0.0, 1e300,
              "Half-width of a gauge's band of particles around its vertical line (in x, and in y in 3D); 0 = one "
              "particle spacing."),
      declare("interval", &Probe::interval, "s", 0.0, 0.0, 1e300, "Sampling interval; 0 = every step."),
    };
    v[1].default_value = std::monostate{};  // a probe must say what it measures
    return v;
  }();
  return params;
}

namespace {

template <class Owner>
int choice_index(const Param<Owner>& p, const std::string& name) {
  const auto it = std::find(p.choices.begin(), p.choices.end(), name);
  return it == p.choices.end() ? -1 : static_cast<int>(it - p.choices.begin());
}

template <class Owner>
const ParamValue& default_in(const Param<Owner>& p, int dimension) {
  return dimension == 3 && !std::holds_alternative<std::monostate>(p.default_3d) ? p.default_3d : p.default_value;
}

template <class Owner>
void set_defaults(Owner& o, const std::vector<Param<Owner>>& params, int dimension) {
  for (const auto& p : params) {
    const ParamValue& def = default_in(p, dimension);
    std::visit(
        [&](auto member) {
          if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
            if (const auto* name = std::get_if<std::string>(&def)) member.set(o, choice_index(p, *name));
          } else {
            using T = std::remove_reference_t<decltype(o.*member)>;
            if (const T* v = std::get_if<T>(&def)) o.*member = *v;
          }
        },
        p.field);
  }
}

Case default_case(int dimension) {
  Case c;
  set_defaults(c, case_params(), dimension);
  c.dimension = dimension;
  return c;
}

std::string format_number(double v) {
  std::string s = fmt::format("{}", v);
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

// A TOML basic string. Control characters are escaped so that any string (a description with a
// newline or a tab, say) reads back unchanged from the template and from checkpoints.
std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    const auto u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (ch == '\n') {
      out += "\\n";
    } else if (ch == '\t') {
      out += "\\t";
    } else if (ch == '\r') {
      out += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      out += fmt::format("\\u{:04X}", static_cast<unsigned>(u));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

// The first `dimension` components, as a TOML array.
std::string format_vector(const Vec3& v, int dimension) {
  std::vector<std::string> components;
  for (int d = 0; d < dimension; ++d) components.push_back(format_number(v[d]));
  return fmt::format("[{}]", fmt::join(components, ", "));
}

std::string format_value(const ParamValue& v, int dimension) {
  return std::visit(
      [dimension](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) return "(required)";
        else if constexpr (std::is_same_v<T, double>) return format_number(x);
        else if constexpr (std::is_same_v<T, int>) return fmt::format("{}", x);
        else if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>) return quote(x);
        else if constexpr (std::is_same_v<T, Vec3>) return format_vector(x, dimension);
        else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
          std::vector<std::string> pairs;
          for (const Vec2& q : x) pairs.push_back(fmt::format("[{}, {}]", format_number(q[0]), format_number(q[1])));
          return fmt::format("[{}]", fmt::join(pairs, ", "));
        } else {
          std::vector<std::string> quoted;
          for (const auto& s : x) quoted.push_back(quote(s));
          return fmt::format("[{}]", fmt::join(quoted, ", "));
        }
      },
      v);
}

template <class Owner>
ParamValue current_value(const Owner& o, const Param<Owner>& p) {
  return std::visit(
      [&](auto member) -> ParamValue {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>)
          return p.choices[static_cast<std::size_t>(member.get(o))];
        else
          return o.*member;
      },
      p.field);
}

template <class Owner>
std::string expectation(const Param<Owner>& p, int dimension) {
  const bool ranged = p.lower <= p.upper;
  const std::string unit = p.unit.empty() ? "" : fmt::format(" ({})", p.unit);
  return std::visit(
      [&](auto member) -> std::string {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
          return fmt::format("one of \"{}\"", fmt::join(p.choices, "\", \""));
        } else {
          using T = std::remove_reference_t<decltype(std::declval<Owner&>().*member)>;
          if constexpr (std::is_same_v<T, double>) {
            if (!ranged) return "a number" + unit;
            if (p.upper >= 1e299) return fmt::format("a number >= {}{}", p.lower, unit);
            return fmt::format("a number from {} to {}{}", p.lower, p.upper, unit);
          } else if constexpr (std::is_same_v<T, int>) {
            if (!ranged) return "an integer" + unit;
            if (p.upper >= 1e8) return fmt::format("an integer >= {}{}", p.lower, unit);
            return fmt::format("an integer from {} to {}{}", p.lower, p.upper, unit);
          } else if constexpr (std::is_same_v<T, bool>) {
            return "true or false";
          } else if constexpr (std::is_same_v<T, std::string>) {
            if (p.choices.empty()) return "a string in quotes";
            return fmt::format("one of \"{}\"", fmt::join(p.choices, "\", \""));
          } else if constexpr (std::is_same_v<T, Vec3>) {
            return (dimension == 3 ? "an array of three numbers [x, y, z]" : "an array of two numbers [x, y]") + unit;
          } else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
            return "an array of points [[x, y], ...]" + unit;
          } else {
            return fmt::format("an array of strings, each one of \"{}\"", fmt::join(p.choices, "\", \""));
          }
        }
      },
      p.field);
}

std::string describe_node(const toml::node& n) {
  std::ostringstream out;
  if (n.is_table()) return "a table";
  if (n.is_array_of_tables()) return "an array of tables";
  if (n.is_string()) {  // as written in a case file, not toml++'s 'literal' form
    std::string s = quote(n.as_string()->get());
    return s.size() > 60 ? s.substr(0, 56) + "...\"" : s;
  }
  n.visit([&](const auto& v) { out << v; });
  std::string s = out.str();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::string where(const std::string& source, const toml::node& n) {
  const auto& region = n.source();
  if (region.begin.line == 0) return source;
  return fmt::format("{}:{}:{}", source, region.begin.line, region.begin.column);
}

[[noreturn]] void fail_value(const std::string& at, const std::string& key, const toml::node& n, const std::string& problem,
                             const std::string& expected) {
  throw CaseError(fmt::format("{}: {} = {}: {}; expected {}", at, key, describe_node(n), problem, expected));
}

template <class Owner>
void assign(Owner& o, const Param<Owner>& p, const toml::node& n, const std::string& at, const std::string& key,
            int dimension) {
  const std::string expected = expectation(p, dimension);
  if (p.only_3d && dimension != 3)
    throw CaseError(fmt::format("{}: {} = {}: a key of 3D cases, and this case is 2D (domain.dimension = {}); leave "
                                "it out, or set domain.dimension = 3",
                                at, key, describe_node(n), dimension));
  auto check_range = [&](double v) {
    if (!std::isfinite(v)) fail_value(at, key, n, "not a finite number", expected);
    if (p.lower <= p.upper && (v < p.lower || v > p.upper)) fail_value(at, key, n, "out of range", expected);
  };
  auto as_number = [&](const toml::node& x) -> std::optional<double> {
    if (x.is_floating_point()) return x.as_floating_point()->get();
    if (x.is_integer()) return static_cast<double>(x.as_integer()->get());
    return std::nullopt;
  };
  auto choose = [&](const std::vector<std::string>& choices) {
    if (!n.is_string()) fail_value(at, key, n, "wrong type", expected);
    const std::string v = n.as_string()->get();
    if (!choices.empty() && std::find(choices.begin(), choices.end(), v) == choices.end()) {
      const auto near = closest_match(v, choices);
      fail_value(at, key, n, near ? fmt::format("unknown value (did you mean \"{}\"?)", *near) : "unknown value",
                 expected);
    }
    return v;
  };
  std::visit(
      [&](auto member) {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>) {
          member.set(o, choice_index(p, choose(p.choices)));
        } else {
          using T = std::remove_reference_t<decltype(o.*member)>;
          if constexpr (std::is_same_v<T, double>) {
            auto v = as_number(n);
            if (!v) fail_value(at, key, n, "wrong type", expected);
            check_range(*v);
            o.*member = *v;
          } else if constexpr (std::is_same_v<T, int>) {
            if (!n.is_integer()) fail_value(at, key, n, "wrong type", expected);
            const auto v = n.as_integer()->get();
            if (v < -2147483647LL || v > 2147483647LL) fail_value(at, key, n, "out of range", expected);
            check_range(static_cast<double>(v));
            o.*member = static_cast<int>(v);
          } else if constexpr (std::is_same_v<T, bool>) {
            if (!n.is_boolean()) fail_value(at, key, n, "wrong type", expected);
            o.*member = n.as_boolean()->get();
          } else if constexpr (std::is_same_v<T, std::string>) {
            o.*member = choose(p.choices);
          } else if constexpr (std::is_same_v<T, Vec3>) {
            const toml::array* a = n.as_array();
            if (a == nullptr) fail_value(at, key, n, "wrong type", expected);
            if (a->size() != static_cast<std::size_t>(dimension))
              fail_value(at, key, n,
                         fmt::format("wrong type ({} component{} in a {}D case, domain.dimension = {})", a->size(),
                                     a->size() == 1 ? "" : "s", dimension, dimension),
                         expected);
            Vec3 v{};
            for (int d = 0; d < dimension; ++d) {
              auto x = as_number(*a->get(static_cast<std::size_t>(d)));
              if (!x || !std::isfinite(*x)) fail_value(at, key, n, "wrong type", expected);
              v[d] = *x;
            }
            o.*member = v;
          } else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
            const toml::array* a = n.as_array();
            if (a == nullptr) fail_value(at, key, n, "wrong type", expected);
            std::vector<Vec2> v;
            for (const auto& item : *a) {
              const toml::array* q = item.as_array();
              if (q == nullptr || q->size() != 2) fail_value(at, key, n, "wrong type", expected);
              Vec2 point{};
              for (int d = 0; d < 2; ++d) {
                auto x = as_number(*q->get(static_cast<std::size_t>(d)));
                if (!x || !std::isfinite(*x)) fail_value(at, key, n, "wrong type", expected);
                point[d] = *x;
              }
              v.push_back(point);
            }
            o.*member = std::move(v);
          } else {
            const toml::array* a = n.as_array();
            if (a == nullptr) fail_value(at, key, n, "wrong type", expected);
            std::vector<std::string> v;
            for (const auto& item : *a) {
              if (!item.is_string()) fail_value(at, key, n, "wrong type", expected);
              const std::string s = item.as_string()->get();
              if (std::find(p.choices.begin(), p.choices.end(), s) == p.choices.end())
                fail_value(at, key, n, fmt::format("unknown entry \"{}\"", s), expected);
              if (std::find(v.begin(), v.end(), s) != v.end())
                fail_value(at, key, n, fmt::format("\"{}\" listed twice", s), expected);
              v.push_back(s);
            }
            o.*member = std::move(v);
          }
        }
      },
      p.field);
}

template <class Owner>
const Param<Owner>* find_param(const std::vector<Param<Owner>>& params, std::string_view key) {
  for (const auto& p : params)
    if (p.key == key) return &p;
  return nullptr;
}

std::vector<std::string> all_keys() {
  std::vector<std::string> keys;
  for (const auto& p : case_params()) keys.push_back(p.key);
  for (const auto& p : region_params()) {
    keys.push_back("water." + p.key);
    keys.push_back("wall." + p.key);
  }
  for (const auto& p : probe_params()) keys.push_back("probe." + p.key);
  return keys;
}

[[noreturn]] void fail_unknown_key(const std::string& at, const std::string& key,
                                   const std::vector<std::string>& candidates) {
  const auto near = closest_match(key, candidates);
  if (near) throw CaseError(fmt::format("{}: unknown key '{}'; did you mean '{}'?", at, key, *near));
  throw CaseError(fmt::format("{}: unknown key '{}'; see `sluice init` for every key", at, key));
}

std::string describe_shape(const Region& r) { return std::string(name_of(r.shape, shape_names)); }
std::string describe_shape(const Probe& p) { return std::string(name_of(p.type, probe_type_names)) + " probe"; }

template <class Owner>
Owner parse_item(const toml::table& t, const std::vector<Param<Owner>>& params, const std::string& section,
                 std::size_t index, const std::string& source, int dimension) {
  Owner item{};
  set_defaults(item, params, dimension);
  std::set<std::string> given;
  for (const auto& [k, node] : t) {
    const std::string key(k.str());
    const std::string full = fmt::format("{}[{}].{}", section, index, key);
    const auto* p = find_param(params, key);
    if (p == nullptr) {
      std::vector<std::string> candidates;
      for (const auto& q : params) candidates.push_back(q.key);
      const auto near = closest_match(key, candidates);
      throw CaseError(fmt::format("{}: unknown key '{}' in [[{}]]{}", where(source, node), key, section,
                                  near ? fmt::format("; did you mean '{}'?", *near)
                                       : fmt::format("; expected one of: {}", fmt::join(candidates, ", "))));
    }
    assign(item, *p, node, where(source, node), full, dimension);
    given.insert(key);
  }
  // Keys that only some items use (a box's min and max, a polygon's points) are required by those
  // items and refused by the others, so that nothing given is silently ignored.
  for (const auto& p : params) {
    const bool required = std::holds_alternative<std::monostate>(p.default_value) || (p.applies && p.applies(item));
    if (required && !given.contains(p.key))
      throw CaseError(fmt::format("{}: [[{}]] number {} has no '{}' ({}); expected {}", where(source, t), section,
                                  index + 1, p.key, p.description, expectation(p, dimension)));
    if (p.applies && !p.applies(item) && given.contains(p.key))
      throw CaseError(fmt::format("{}: [[{}]] number {} gives '{}', which a {} does not use ({})", where(source, t),
                                  section, index + 1, p.key, describe_shape(item), p.description));
  }
  return item;
}

}  // namespace

Case parse_case(std::string_view toml_text, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(toml_text, source);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw CaseError(fmt::format("{}:{}:{}: not valid TOML: {}", source, b.line, b.column, e.description()));
  }
  // The dimension first: the defaults (gravity) and every vector's length follow from it.
  int dimension = 2;
  if (const toml::node* d = root.at_path("domain.dimension").node()) {
    Case probe;
    assign(probe, *find_param(case_params(), "domain.dimension"), *d, where(source, *d), "domain.dimension", 2);
    dimension = probe.dimension;
  }
  Case c = default_case(dimension);
  std::vector<std::string> section_names;
  for (const auto& s : case_sections()) section_names.push_back(s.name);

  for (const auto& [k, node] : root) {
    const std::string name(k.str());
    const auto section = std::find_if(case_sections().begin(), case_sections().end(),
                                      [&](const Section& s) { return s.name == name; });
    if (section == case_sections().end()) {
      if (!node.is_table() && !node.is_array()) {  // a key written before any [section] header
        const auto near = closest_match(name, all_keys());
        throw CaseError(fmt::format("{}: key '{}' is outside any section; {}", where(source, node), name,
                                    near ? fmt::format("did you mean '{}' (key '{}' under [{}])?", *near,
                                                       near->substr(near->find('.') + 1),
                                                       near->substr(0, near->find('.')))
                                         : std::string("keys belong under a [section] header; see `sluice init`")));
      }
      const auto near = closest_match(name, section_names);
      throw CaseError(fmt::format("{}: unknown section '{}'{}", where(source, node), name,
                                  near ? fmt::format("; did you mean '{}'?", *near)
                                       : fmt::format("; expected one of: {}", fmt::join(section_names, ", "))));
    }
    if (section->is_array) {
      const toml::array* items = node.as_array();
      if (items == nullptr || !items->is_array_of_tables())
        throw CaseError(fmt::format("{}: '{}' must be written as [[{}]] tables", where(source, node), name, name));
      std::size_t index = 0;
      for (const auto& item : *items) {
        const toml::table& t = *item.as_table();
        if (name == "water") c.water.push_back(parse_item(t, region_params(), name, index, source, dimension));
        else if (name == "wall") c.walls.push_back(parse_item(t, region_params(), name, index, source, dimension));
        else c.probes.push_back(parse_item(t, probe_params(), name, index, source, dimension));
        ++index;
      }
      continue;
    }
    const toml::table* table = node.as_table();
    if (table == nullptr)
      throw CaseError(fmt::format("{}: '{}' must be a section [{}] holding keys", where(source, node), name, name));
    for (const auto& [sub, value] : *table) {
      const std::string key = name + "." + std::string(sub.str());
      const auto* p = find_param(case_params(), key);
      if (p == nullptr) fail_unknown_key(where(source, value), key, all_keys());
      assign(c, *p, value, where(source, value), key, dimension);
    }
  }
  validate_case(c, source);
  return c;
}

Case load_case_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw CaseError(fmt::format("{}: no such case file (and no built-in case of that name; see `sluice cases`)",
                                path.string()));
  if (std::filesystem::is_directory(path, ec))
    throw CaseError(fmt::format("{}: is a directory; expected a case file (.toml)", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CaseError(fmt::format("{}: cannot be read", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_case(text.str(), path.string());
}

namespace {

// The value of `--set key=text` for parameter p, as a TOML node held under "value" in the returned
// table. The text is TOML ("0.1", "[3.0, 4.0]", "\"euler\""); a bare word is taken as a string, so
// time.integrator=euler and case.name=2024 mean the strings, and a string list may be written bare
// (output.formats=npz,vtk or [npz, vtk]) since shells strip the quotes from ["npz", "vtk"].
template <class Owner>
toml::table override_value(const Param<Owner>& p, const std::string& text, const std::string& at, int dimension) {
  if (text.empty())
    throw CaseError(fmt::format("{}: no value after '='; expected {}", at, expectation(p, dimension)));
  std::optional<toml::table> parsed;
  try {
    const std::string document = "value = " + text;
    toml::table t = toml::parse(std::string_view(document), std::string_view("--set"));
    if (t.size() == 1 && t.contains("value")) parsed = std::move(t);  // "1\nother = 2" is not one value
  } catch (const toml::parse_error&) {
  }
  const bool quoted = text.front() == '"' || text.front() == '\'';
  if (std::holds_alternative<std::string Owner::*>(p.field) || std::holds_alternative<ChoiceField<Owner>>(p.field)) {
    if (parsed && parsed->get("value")->is_string()) return *parsed;
    if (!quoted) return toml::table{{"value", text}};
  } else if (std::holds_alternative<std::vector<std::string> Owner::*>(p.field)) {
    if (parsed && parsed->get("value")->is_array()) return *parsed;
    std::string_view list = text;
    if (list.size() >= 2 && list.front() == '[' && list.back() == ']') list = list.substr(1, list.size() - 2);
    toml::array items;
    while (true) {
      const auto comma = list.find(',');
      std::string item(list.substr(0, comma));
      item.erase(0, item.find_first_not_of(" \t"));
      item.erase(item.find_last_not_of(" \t") + 1);
      if (item.size() >= 2 && (item.front() == '"' || item.front() == '\'') && item.back() == item.front())
        item = item.substr(1, item.size() - 2);
      if (!item.empty()) items.push_back(item);
      if (comma == std::string_view::npos) break;
      list.remove_prefix(comma + 1);
    }
    return toml::table{{"value", std::move(items)}};
  }
  if (parsed) return *parsed;
  return toml::table{{"value", text}};  // not TOML: shown as given in the "wrong type" message
}

void apply_one_override(Case& c, std::string_view assignment) {
  const std::string at = fmt::format("--set {}", assignment);
  const auto eq = assignment.find('=');
  if (eq == std::string_view::npos)
    throw CaseError(fmt::format("{}: expected key=value, for example --set domain.dx=0.1", at));
  auto trim = [](std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return std::string(s);
  };
  const std::string key = trim(assignment.substr(0, eq));
  const std::string text = trim(assignment.substr(eq + 1));
  if (key.empty())
    throw CaseError(fmt::format("{}: no key before '='; expected key=value, for example --set domain.dx=0.1", at));

  static const std::regex item_key(R"(^(water|wall|probe)(?:\[(\d+)\]|\.(\d+))\.(\w+)$)");
  std::smatch m;
  if (std::regex_match(key, m, item_key)) {
    const std::string section = m[1];
    const std::string digits = m[2].matched ? m[2].str() : m[3].str();
    const std::string sub = m[4];
    auto apply = [&](auto& items, const auto& params) {
      // Compare as text first: an index too long for an integer is simply out of range.
      const std::size_t index = digits.size() > 9 ? std::numeric_limits<std::size_t>::max() : std::stoul(digits);
      if (index >= items.size())
        throw CaseError(fmt::format("{}: the case has {} [[{}]] entr{} (numbered from 0); there is no {}[{}]", at,
                                    items.size(), section, items.size() == 1 ? "y" : "ies", section, digits));
      const auto* p = find_param(params, sub);
      if (p == nullptr) {
        std::vector<std::string> candidates;
        for (const auto& q : params) candidates.push_back(q.key);
        const auto near = closest_match(sub, candidates);
        throw CaseError(fmt::format("{}: unknown key '{}' in [[{}]]; {}", at, sub, section,
                                    near ? fmt::format("did you mean '{}[{}].{}'?", section, digits, *near)
                                         : fmt::format("expected one of: {}", fmt::join(candidates, ", "))));
      }
      const toml::table holder = override_value(*p, text, at, c.dimension);
      assign(items[index], *p, *holder.get("value"), at, key, c.dimension);
    };
    if (section == "water") apply(c.water, region_params());
    else if (section == "wall") apply(c.walls, region_params());
    else apply(c.probes, probe_params());
  } else {
    const auto* p = find_param(case_params(), key);
    if (p == nullptr) fail_unknown_key(at, key, all_keys());
    // Every vector of the case and its defaults follow the dimension: it is the case file's to say.
    if (key == "domain.dimension")
      throw CaseError(fmt::format("{}: the dimension cannot be changed with --set (the case's vectors and defaults "
                                  "follow it); write domain.dimension in the case file",
                                  at));
    const toml::table holder = override_value(*p, text, at, c.dimension);
    assign(c, *p, *holder.get("value"), at, key, c.dimension);
  }
}

}  // namespace

void apply_override(Case& c, std::string_view assignment) {
  apply_one_override(c, assignment);
  validate_case(c, fmt::format("--set {}", assignment));
}

void apply_overrides(Case& c, const std::vector<std::string>& assignments) {
  for (const auto& a : assignments) apply_one_override(c, a);
  if (!assignments.empty())
    validate_case(c, fmt::format("with --set {}", fmt::join(assignments, " --set ")));
}

void validate_case(const Case& c, const std::string& source) {
  auto fail = [&](const std::string& what) { throw CaseError(fmt::format("{}: {}", source, what)); };
  const double h = c.smoothing_length();
  const int dim = c.dimension;
  // The name is the default output folder out/<name> and the .pvd file's name: it must be one plain
  // path component.
  const bool control_char = std::any_of(c.name.begin(), c.name.end(), [](char ch) {
    return static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) == 0x7f;
  });
  if (c.name.empty() || c.name == "." || c.name == ".." || c.name.find_first_of("/\\") != std::string::npos ||
      control_char)
    fail(fmt::format("case.name = {}: not a usable name; expected a non-empty name without slashes or control "
                     "characters, other than \".\" and \"..\" (it names the output folder out/<name>)",
                     quote(c.name)));
  const Vec3 tank = c.tank_size();
  std::vector<std::string> sizes;
  for (int d = 0; d < dim; ++d) sizes.push_back(fmt::format("{} m", tank[d]));
  for (int d = 0; d < dim; ++d)
    if (tank[d] < 2.0 * c.dx)
      fail(fmt::format("the tank ({}) is smaller than two particle spacings (dx = {} m)", fmt::join(sizes, " x "),
                       c.dx));
  if (c.water.empty()) fail("no [[water]] region; a case needs at least one");
  // A region's bounding box, after checking its shape.
  auto check_region = [&](const Region& r, const std::string& what, std::size_t i) -> std::pair<Vec3, Vec3> {
    if (r.shape == Shape::box) {
      for (int d = 0; d < dim; ++d)
        if (!(r.min[d] < r.max[d]))
          fail(fmt::format("[[{}]] number {}: min {} must be below max {} in every component (a box needs both)",
                           what, i + 1, format_vector(r.min, dim), format_vector(r.max, dim)));
      return {r.min, r.max};
    }
    if (dim != 2)
      fail(fmt::format("[[{}]] number {}: a polygon is a 2D shape and this case is {}D; expected shape = \"box\"",
                       what, i + 1, dim));
    if (r.points.size() < 3)
      fail(fmt::format("[[{}]] number {}: a polygon needs at least 3 points, got {}", what, i + 1, r.points.size()));
    Vec3 lo{r.points[0][0], r.points[0][1], 0.0}, hi = lo;
    double twice_area = 0.0;
    for (std::size_t k = 0, j = r.points.size() - 1; k < r.points.size(); j = k++) {
      for (int d = 0; d < 2; ++d) {
        lo[d] = std::min(lo[d], r.points[k][d]);
        hi[d] = std::max(hi[d], r.points[k][d]);
      }
      twice_area += r.points[j][0] * r.points[k][1] - r.points[k][0] * r.points[j][1];
    }
    if (std::abs(twice_area) < 1e-12 * std::max(1.0, (hi[0] - lo[0]) * (hi[1] - lo[1])))
      fail(fmt::format("[[{}]] number {}: the polygon's points enclose no area", what, i + 1));
    return {lo, hi};
  };
  std::vector<std::string> extent;
  for (int d = 0; d < dim; ++d) extent.push_back(fmt::format("[0, {}]", tank[d]));
  for (std::size_t i = 0; i < c.water.size(); ++i) {
    const auto [lo, hi] = check_region(c.water[i], "water", i);
    const double tol = 1e-9 * *std::max_element(tank.begin(), tank.begin() + dim);
    for (int d = 0; d < dim; ++d)
      if (lo[d] < -tol || hi[d] > tank[d] + tol)
        fail(fmt::format("[[water]] number {} (from {} to {}) reaches outside the tank {}", i + 1,
                         format_vector(lo, dim), format_vector(hi, dim), fmt::join(extent, " x ")));
  }
  for (std::size_t i = 0; i < c.walls.size(); ++i) check_region(c.walls[i], "wall", i);
  std::set<std::string> names;
  for (std::size_t i = 0; i < c.probes.size(); ++i) {
    const Probe& p = c.probes[i];
    if (p.name.empty() || p.name.find_first_of("/\\ ") != std::string::npos)
      fail(fmt::format("[[probe]] number {}: name \"{}\" must be non-empty, without spaces or slashes", i + 1, p.name));
    if (!names.insert(p.name).second) fail(fmt::format("[[probe]] name \"{}\" is used twice", p.name));
    if (p.type == ProbeType::front && norm(p.direction) == 0.0)
      fail(fmt::format("[[probe]] \"{}\": direction must not be {}", p.name, format_vector(p.direction, dim)));
  }
  if (c.output_formats.empty()) fail("output.formats is empty; expected at least one of \"vtk\", \"npz\"");
  const double max_points = 5e8;
  double lattice_points = 1.0;
  for (int d = 0; d < dim; ++d) lattice_points *= (tank[d] + 4 * h) / c.dx;
  if (lattice_points > max_points)
    fail(fmt::format("domain.dx = {} m gives more than {:.0e} lattice points in the tank; expected a larger dx",
                     c.dx, max_points));
}

std::string case_template(const Case& c) {
  std::string out;
  out += "# sluice case file (TOML). Every key is listed with its unit, default and allowed range;\n";
  out += "# delete a key to use its default. Run it with:  sluice run <this file>\n";
  auto comment_lines = [&](const std::string& text, const std::string& indent) {
    out += indent + "# " + text + "\n";
  };
  auto describe = [&](const auto& p, const std::string& indent) {
    comment_lines(p.description, indent);
    std::vector<std::string> facts;
    if (!p.unit.empty()) facts.push_back("unit: " + p.unit);
    const ParamValue& def = default_in(p, c.dimension);
    facts.push_back(std::holds_alternative<std::monostate>(def) ? std::string("required")
                                                                : "default: " + format_value(def, c.dimension));
    facts.push_back("allowed: " + expectation(p, c.dimension));
    comment_lines(fmt::format("{}", fmt::join(facts, " | ")), indent);
  };
  for (const auto& s : case_sections()) {
    out += "\n";
    comment_lines(s.description, "");
    if (!s.is_array) {
      out += fmt::format("[{}]\n", s.name);
      for (const auto& p : case_params()) {
        if (p.key.rfind(s.name + ".", 0) != 0 || (p.only_3d && c.dimension != 3)) continue;
        describe(p, "");
        out += fmt::format("{} = {}\n", p.key.substr(s.name.size() + 1),
                           format_value(current_value(c, p), c.dimension));
      }
      continue;
    }
    auto write_items = [&](const auto& items, const auto& params) {
      comment_lines(fmt::format("Keys of each [[{}]]:", s.name), "");
      for (const auto& p : params) {
        out += fmt::format("#   {}:\n", p.key);
        describe(p, "#     ");
      }
      if (items.empty()) comment_lines(fmt::format("(this case has no [[{}]] entries)", s.name), "");
      for (const auto& item : items) {
        out += fmt::format("[[{}]]\n", s.name);
        for (const auto& p : params)
          if (p.applies == nullptr || p.applies(item))
            out += fmt::format("{} = {}\n", p.key, format_value(current_value(item, p), c.dimension));
      }
    };
    if (s.name == "water") write_items(c.water, region_params());
    else if (s.name == "wall") write_items(c.walls, region_params());
    else write_items(c.probes, probe_params());
  }
  return out;
}

const std::vector<BuiltinCase>& builtin_cases() {
  static const std::vector<BuiltinCase> cases = [] {
    std::vector<BuiltinCase> v;
    for (std::size_t i = 0; i < detail::builtin_case_count; ++i)
      v.push_back({detail::builtin_case_texts[i].name, detail::builtin_case_texts[i].text});
    return v;
  }();
  return cases;
}

std::optional<Case> load_builtin_case(std::string_view name) {
  for (const auto& b : builtin_cases())
    if (b.name == name) return parse_case(b.text, fmt::format("built-in case '{}'", b.name));
  return std::nullopt;
}

std::optional<std::string> closest_match(std::string_view word, const std::vector<std::string>& candidates) {
  auto distance = [](std::string_view a, std::string_view b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    // Compare with the whole key and with its last part, so "domain.ddx" and "ddx" both find "domain.dx".
    std::size_t d = distance(word, c);
    const auto dot_pos = c.rfind('.');
    if (dot_pos != std::string::npos && word.find('.') == std::string_view::npos)
      d = std::min(d, distance(word, std::string_view(c).substr(dot_pos + 1)));
    // A word that is the start of a candidate ("wendland" for "wendland_c2") is a likely abbreviation.
    if (word.size() >= 3 && std::string_view(c).starts_with(word)) d = std::min<std::size_t>(d, 1);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace sluice
