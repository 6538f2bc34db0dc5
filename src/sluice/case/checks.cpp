#include "sluice/case/checks.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

#include "sluice/core/body_id.hpp"
#include "sluice/geometry/wave_theory.hpp"

#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace {

std::string point_text(const Vec2& p) { return fmt::format("({}, {})", p[0], p[1]); }

// Which side of the line from a to b c lies on: +1 left, -1 right, 0 on it (within a relative
// 1e-12 of the triangle's scale, so that a point computed to lie on the line counts as on it).
int side(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double twice_area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  const double scale =
      (std::abs(b[0] - a[0]) + std::abs(b[1] - a[1])) * (std::abs(c[0] - a[0]) + std::abs(c[1] - a[1]));
  if (std::abs(twice_area) <= 1e-12 * scale) return 0;
  return twice_area > 0.0 ? 1 : -1;
}

// p, on the line through a and b, lies between them.
bool within(const Vec2& a, const Vec2& b, const Vec2& p) {
  return std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= p[1] &&
         p[1] <= std::max(a[1], b[1]);
}

// How the segments ab and cd meet: "crosses" (each passes through the other), "touches" (an end of
// one lies on the other, or they overlap along a line), or empty if they have no point in common.
std::string_view meeting(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (std::max(a[0], b[0]) < std::min(c[0], d[0]) || std::max(c[0], d[0]) < std::min(a[0], b[0]) ||
      std::max(a[1], b[1]) < std::min(c[1], d[1]) || std::max(c[1], d[1]) < std::min(a[1], b[1]))
    return {};
  const int sa = side(c, d, a), sb = side(c, d, b), sc = side(a, b, c), sd = side(a, b, d);
  if (sa * sb < 0 && sc * sd < 0) return "crosses";
  if ((sa == 0 && within(c, d, a)) || (sb == 0 && within(c, d, b)) || (sc == 0 && within(a, b, c)) ||
      (sd == 0 && within(a, b, d)))
    return "touches";
  return {};
}

// Raises the problems of one case, all prefixed with where the case came from.
struct Checker {
  const Case& c;
  const std::string& source;

  [[noreturn]] void fail(const std::string& what) const { throw CaseError(fmt::format("{}: {}", source, what)); }

  // The name is the default output folder out/<name> and the .pvd file's name: it must be one plain
  // path component.
  void check_name() const {
    const bool control_char = std::any_of(c.name.begin(), c.name.end(), [](char ch) {
      return static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) == 0x7f;
    });
    if (c.name.empty() || c.name == "." || c.name == ".." || c.name.find_first_of("/\\") != std::string::npos ||
        control_char)
      fail(fmt::format("case.name = {}: not a usable name; expected a non-empty name without slashes or control "
                       "characters, other than \".\" and \"..\" (it names the output folder out/<name>)",
                       quote(c.name)));
    // The longest file name made of it is the .pvd file's temporary <name>.pvd.tmp<process id>
    // (io/atomic_file.cpp), a process id having up to 7 digits (Linux's pid_max is at most 2^22): it
    // must fit in a file name of 255 bytes, or the run fails after writing its first frame.
    constexpr std::size_t longest_file_name = 255;
    constexpr std::size_t max_length = longest_file_name - std::string_view(".pvd.tmp4194304").size();
    if (c.name.size() > max_length) {
      std::size_t shown = 40;  // the start of the name, cut between two UTF-8 characters
      while (shown > 0 && (static_cast<unsigned char>(c.name[shown]) & 0xC0u) == 0x80u) --shown;
      fail(fmt::format("case.name = {}...: too long, {} bytes; expected at most {} bytes (it names the output folder "
                       "out/<name> and the file <name>.pvd in it, written through a temporary <name>.pvd.tmp<process "
                       "id>, and a file name holds at most {} bytes)",
                       quote(c.name.substr(0, shown)), c.name.size(), max_length, longest_file_name));
    }
  }

  void check_tank_size() const {
    const Vec3 tank = c.tank_size();
    std::vector<std::string> sizes;
    for (int d = 0; d < c.dimension; ++d) sizes.push_back(fmt::format("{} m", tank[d]));
    for (int d = 0; d < c.dimension; ++d)
      if (tank[d] < 2.0 * c.dx)
        fail(fmt::format("the tank ({}) is smaller than two particle spacings (dx = {} m)", fmt::join(sizes, " x "),
                         c.dx));
  }

  // The bounding box of a box region, after checking that it has an inside.
  std::pair<Vec3, Vec3> box_bounds(const Region& r, const std::string& what, std::size_t i) const {
    for (int d = 0; d < c.dimension; ++d)
      if (!(r.min[d] < r.max[d]))
        fail(fmt::format("[[{}]] number {}: min {} must be below max {} in every component (a box needs both)", what,
                         i + 1, format_vector(r.min, c.dimension), format_vector(r.max, c.dimension)));
    return {r.min, r.max};
  }

  // The bounding box of a polygon region, after checking that it is 2D and encloses an area.
  std::pair<Vec3, Vec3> polygon_bounds(const Region& r, const std::string& what, std::size_t i) const {
    if (c.dimension != 2)
      fail(fmt::format("[[{}]] number {}: a polygon is a 2D shape and this case is {}D; expected shape = \"box\"",
                       what, i + 1, c.dimension));
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
    check_simple_polygon(r.points, what, i);
    if (std::abs(twice_area) < 1e-12 * std::max(1.0, (hi[0] - lo[0]) * (hi[1] - lo[1])))
      fail(fmt::format("[[{}]] number {}: the polygon's points enclose no area", what, i + 1));
    return {lo, hi};
  }

  // The set-up fills a polygon by the crossing rule and lays its wall particles along its edges: a
  // polygon whose edges cross or touch has no single inside, and an edge of no length no direction.
  // Edge k runs from point k to point k + 1 (the last back to point 1). Two edges after one another
  // share a corner; one that turns back along the other is caught too, as an end of one of them then
  // lies on the edge before or after the other (with 3 points, the polygon encloses no area).
  void check_simple_polygon(const std::vector<Vec2>& points, const std::string& what, std::size_t i) const {
    const std::size_t n = points.size();
    const std::string expected = "expected a simple polygon, whose edges meet only at the corners they share";
    // Repeated points, found in sorted order.
    std::vector<std::size_t> order(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return points[a] < points[b] || (points[a] == points[b] && a < b);
    });
    for (std::size_t k = 1; k < n; ++k) {
      const std::size_t a = order[k - 1], b = order[k];
      if (points[a] != points[b]) continue;
      if (b == a + 1 || (a == 0 && b == n - 1))
        fail(fmt::format("[[{}]] number {}: points {} and {} are the same point {}, so that edge {} has no length; "
                         "expected distinct points one after another (the polygon closes itself from its last point "
                         "back to its first: the first point is not repeated at the end)",
                         what, i + 1, a + 1, b + 1, point_text(points[a]), b == a + 1 ? a + 1 : n));
      fail(fmt::format("[[{}]] number {}: points {} and {} are the same point {}: the polygon touches itself there; {}",
                       what, i + 1, a + 1, b + 1, point_text(points[a]), expected));
    }
    const auto edge_text = [&](std::size_t k) {
      return fmt::format("edge {} (from {} to {})", k + 1, point_text(points[k]), point_text(points[(k + 1) % n]));
    };
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t m = k + 2; m < n; ++m) {
        if (k == 0 && m == n - 1) continue;  // the last edge ends where the first begins
        const std::string_view how = meeting(points[k], points[(k + 1) % n], points[m], points[(m + 1) % n]);
        if (!how.empty())
          fail(fmt::format("[[{}]] number {}: the polygon {} itself: {} {} {}; {}", what, i + 1, how, edge_text(k), how,
                           edge_text(m), expected));
      }
  }

  // The bounding box of a mesh region, read and checked by load_meshes (case/meshes.hpp).
  std::pair<Vec3, Vec3> mesh_bounds(const Region& r, const std::string& what, std::size_t i) const {
    if (c.dimension != 3 || r.mesh == nullptr)
      fail(fmt::format("[[{}]] number {}: {}[{}].shape = \"mesh\" needs a 3D case with its mesh read", what, i + 1,
                       what, i));
    return {r.mesh->lower(), r.mesh->upper()};
  }

  std::pair<Vec3, Vec3> region_bounds(const Region& r, const std::string& what, std::size_t i) const {
    switch (r.shape) {
      case Shape::box: return box_bounds(r, what, i);
      case Shape::polygon: return polygon_bounds(r, what, i);
      case Shape::mesh: return mesh_bounds(r, what, i);
    }
    return box_bounds(r, what, i);
  }

  // A region's bounding box within the tank (with a relative tolerance).
  void check_inside_tank(const std::pair<Vec3, Vec3>& bounds, const std::string& what, std::size_t i,
                         const std::string& kind) const {
    const Vec3 tank = c.tank_size();
    std::vector<std::string> extent;
    for (int d = 0; d < c.dimension; ++d) extent.push_back(fmt::format("[0, {}]", tank[d]));
    const double tol = 1e-9 * *std::max_element(tank.begin(), tank.begin() + c.dimension);
    const auto& [lo, hi] = bounds;
    for (int d = 0; d < c.dimension; ++d)
      if (lo[d] < -tol || hi[d] > tank[d] + tol)
        fail(fmt::format("[[{}]] number {} ({}from {} to {}) reaches outside the tank {}", what, i + 1, kind,
                         format_vector(lo, c.dimension), format_vector(hi, c.dimension), fmt::join(extent, " x ")));
  }

  void check_water() const {
    if (c.water.empty()) fail("no [[water]] region; a case needs at least one");
    for (std::size_t i = 0; i < c.water.size(); ++i) {
      check_inside_tank(region_bounds(c.water[i], "water", i), "water", i,
                        c.water[i].shape == Shape::mesh ? "a mesh " : "");
      if (c.water[i].shape == Shape::box) check_box_holds_water(c.water[i], i);
    }
  }

  // Water fills the lattice points (i + 1/2) dx inside a region (geometry/setup.cpp): a box too thin
  // to hold one along some axis would start the run without that water.
  void check_box_holds_water(const Region& r, std::size_t i) const {
    const double tol = 1e-9 * c.dx;
    for (int d = 0; d < c.dimension; ++d) {
      const double first = std::ceil((r.min[d] - tol) / c.dx - 0.5), last = std::floor((r.max[d] + tol) / c.dx - 0.5);
      if (last < first)
        fail(fmt::format("[[water]] number {} (box from {} to {}) holds no water particle at domain.dx = {} m: it is "
                         "{:g} m across along {}, between the points (i + 1/2) dx that water fills; expected a region "
                         "at least dx across, or a smaller domain.dx",
                         i + 1, format_vector(r.min, c.dimension), format_vector(r.max, c.dimension), c.dx,
                         r.max[d] - r.min[d], "xyz"[d]));
    }
  }

  // Boxes and polygons may reach into the tank's walls; a mesh, whose filling is a lattice of its own,
  // must lie inside the tank.
  void check_walls() const {
    if (c.walls.size() > static_cast<std::size_t>(body_id::most_walls))
      fail(fmt::format("{} [[wall]] regions; a case can have at most {}", c.walls.size(), body_id::most_walls));
    for (std::size_t i = 0; i < c.walls.size(); ++i) {
      const auto bounds = region_bounds(c.walls[i], "wall", i);
      if (c.walls[i].shape == Shape::mesh) check_inside_tank(bounds, "wall", i, "a mesh ");
    }
  }

  void check_probes() const {
    std::set<std::string> names;
    for (std::size_t i = 0; i < c.probes.size(); ++i) {
      const Probe& p = c.probes[i];
      if (p.name.empty() || p.name.find_first_of("/\\ ") != std::string::npos)
        fail(fmt::format("[[probe]] number {}: name {} must be non-empty, without spaces or slashes", i + 1,
                         quote(p.name)));
      if (!names.insert(p.name).second) fail(fmt::format("[[probe]] name {} is used twice", quote(p.name)));
      if (p.type == ProbeType::front && norm(p.direction) == 0.0)
        fail(fmt::format("[[probe]] {}: direction must not be {}", quote(p.name),
                         format_vector(p.direction, c.dimension)));
      check_probe_inside_tank(p);
      check_probe_wall(p);
    }
  }

  // A probe that moves with a wall names one of the case's walls.
  void check_probe_wall(const Probe& p) const {
    if (p.wall.empty() || (p.wall == "tank" && c.tank_moves())) return;
    if (p.wall == "tank")
      fail(fmt::format("[[probe]] {}: wall = \"tank\" moves the probe with the tank's own walls, but this case's tank "
                       "does not move; expected a [tank.translation] or [tank.rotation] law, or no wall key",
                       quote(p.name)));
    std::vector<std::string> names;
    for (const Region& w : c.walls) {
      if (w.name == p.wall) return;
      names.push_back(quote(w.name));
    }
    fail(fmt::format("[[probe]] {}: wall = {} names no [[wall]] of the case; expected {}", quote(p.name),
                     quote(p.wall),
                     names.empty() ? std::string("no wall key (the case has no [[wall]]), or a [[wall]] to move with")
                                   : fmt::format("one of {}", fmt::join(names, ", "))));
  }

  // Every probe samples the particles around its point (a pressure probe), on the vertical line
  // through it from its foot (a gauge) or measures from it (a front): outside the tank a pressure
  // probe or a gauge finds no water and records zeros for the whole run.
  void check_probe_inside_tank(const Probe& p) const {
    const Vec3 tank = c.tank_size();
    const double tol = 1e-9 * *std::max_element(tank.begin(), tank.begin() + c.dimension);
    std::vector<std::string> extent;
    for (int d = 0; d < c.dimension; ++d) extent.push_back(fmt::format("[0, {}]", tank[d]));
    const std::string at = format_vector(p.point, c.dimension);
    const std::string what = p.type == ProbeType::pressure ? "a pressure probe at " + at
                             : p.type == ProbeType::gauge  ? "a gauge on the vertical line through " + at
                                                           : "a front probe measuring from " + at;
    for (int d = 0; d < c.dimension; ++d)
      if (!(p.point[d] >= -tol && p.point[d] <= tank[d] + tol))
        fail(fmt::format("[[probe]] {} ({}) lies outside the tank {}: {} = {} is not within [0, {}]; expected a point "
                         "inside the tank",
                         quote(p.name), what, fmt::join(extent, " x "), "xyz"[d], p.point[d], tank[d]));
  }

  // The wall function replaces the wall friction: it adds to walls that have none of their own, and
  // measures the distance from the wall surface, where such walls hold the water (dx/2 off it).
  void check_wall_friction() const {
    if (c.wall_friction != WallFriction::log_law) return;
    const bool frictionless = c.wall_boundary == WallBoundary::adami ||
                              (c.wall_boundary == WallBoundary::mdbc && c.wall_slip == WallSlip::free_slip);
    if (!frictionless)
      fail(fmt::format("physics.wall_friction = \"log_law\" with physics.wall_boundary = \"{}\"{}: those walls have "
                       "a friction of their own (the artificial viscosity between water and wall){}; expected "
                       "physics.wall_boundary = \"mdbc\" with physics.wall_slip = \"free_slip\", or \"adami\"",
                       wall_boundary_names[static_cast<std::size_t>(c.wall_boundary)],
                       c.wall_boundary == WallBoundary::mdbc ? " and physics.wall_slip = \"no_slip\"" : "",
                       c.wall_boundary == WallBoundary::dynamic ? " and hold moving water about 1.5 dx off the wall" : ""));
    if (!(c.viscosity > 0.0))
      fail("physics.wall_friction = \"log_law\" needs the water's viscosity: fluid.viscosity is 0; expected a "
           "positive dynamic viscosity (water: 0.001 Pa s)");
  }

  // Each wall is a body: a name that is one plain path component (bodies/<name>.csv), unique; and a
  // motion whose laws can be evaluated.
  void check_bodies() const {
    std::set<std::string> names;
    for (std::size_t i = 0; i < c.walls.size(); ++i) {
      const Region& w = c.walls[i];
      const bool plain = !w.name.empty() && w.name.size() <= 64 && w.name != "." && w.name != ".." &&
                         std::all_of(w.name.begin(), w.name.end(), [](char ch) {
                           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == '.';
                         });
      if (!plain)
        fail(fmt::format("wall[{}].name = {}: expected 1 to 64 letters, digits, '_', '-' or '.' (it names the file "
                         "bodies/<name>.csv)",
                         i, quote(w.name)));
      if (!names.insert(w.name).second)
        fail(fmt::format("wall[{}].name = {}: another wall has that name; expected each wall's name once", i,
                         quote(w.name)));
      if (w.name == "tank" || w.name == "water")
        fail(fmt::format("wall[{}].name = {}: that name belongs to the {} (bodies/{}.csv); expected another name", i,
                         quote(w.name), w.name == "tank" ? "tank's own walls" : "water", w.name));
      const bool absorbs = w.translation.law == MotionLawType::absorber || (w.translation.absorb && w.translation.law == MotionLawType::wave);
      if (absorbs && w.rotation.law != MotionLawType::none)
        fail(fmt::format("wall[{}] ({}) absorbs waves and turns: an absorbing piston only translates; expected no "
                         "[wall.rotation] on it",
                         i, quote(w.name)));
      if (w.floats) check_floating(i, w);
      // A wall fixed in space inside a tank that moves would cut through the tank's walls or its water.
      if (c.tank_moves() && !w.moves())
        fail(fmt::format("wall[{}] ({}) is fixed while the tank moves; expected it to move with the tank (give it "
                         "the tank's [tank.translation] / [tank.rotation] laws as its own) or another motion",
                         i, quote(w.name)));
    }
    for_each_motion_law(c, [&](const MotionLawSpec& m, const std::string& key, bool rotation) {
      if (m.law == MotionLawType::none) return;
      const Vec3& v = rotation ? m.axis : m.direction;
      double length = 0.0;
      for (int d = 0; d < c.dimension; ++d) length += v[d] * v[d];
      if (!(rotation && c.dimension == 2) && !(length > 0.0))
        fail(fmt::format("{}.{} = {}: a vector of length 0; expected the {}", key, rotation ? "axis" : "direction",
                         format_vector(v, c.dimension), rotation ? "axis of rotation" : "direction of motion"));
      if ((m.law == MotionLawType::linear || m.law == MotionLawType::polynomial) && !(m.end > m.start))
        fail(fmt::format("{}.end = {} s is not after its start, {} s; expected end > start", key, m.end, m.start));
      const bool periodic = m.law == MotionLawType::sinusoidal ||
                            (m.law == MotionLawType::wave && m.spectrum == WaveSpectrum::regular);
      if (periodic && !(m.period > 0.0))
        fail(fmt::format("{}.period = {} s: a {} law needs its period; expected a period > 0", key, m.period,
                         name_of(m.law, motion_law_names)));
      if (m.law == MotionLawType::wave && key.rfind("tank.", 0) == 0)
        fail(fmt::format("{}.law = \"wave\": the tank cannot be a wave maker; expected a [[wall]] with law = \"wave\" "
                         "as the paddle (a piston or a flap) inside the tank",
                         key));
      if (m.law == MotionLawType::wave) check_wave_maker(m, key, rotation);
      if (m.law == MotionLawType::absorber || m.absorb) check_absorber(m, key, rotation);
      if (m.law == MotionLawType::polynomial && m.coefficients.empty())
        fail(fmt::format("{}.coefficients is empty: a polynomial law needs them; expected [c0, c1, ...]", key));
    });
  }

  // A floating wall: no motion laws beside it, one of mass and density, a positive inertia, known
  // degrees of freedom, per-degree vectors of the right length, an anchor for every spring.
  void check_floating(std::size_t i, const Region& w) const {
    const FloatingSpec& f = w.floating;
    const std::string key = fmt::format("wall[{}].floating", i);
    const int dim = c.dimension;
    if (w.translation.law != MotionLawType::none || w.rotation.law != MotionLawType::none)
      fail(fmt::format("wall[{}] ({}) floats and has a [wall.{}] law: a floating body is moved by the water; expected "
                       "either [wall.floating] or motion laws",
                       i, quote(w.name), w.translation.law != MotionLawType::none ? "translation" : "rotation"));
    if ((f.mass > 0.0) == (f.density > 0.0))
      fail(fmt::format("{}: mass = {} kg and density = {} kg/m^3; expected one of them, > 0 (the other 0)", key, f.mass,
                       f.density));
    const std::vector<std::string> dofs = floating_dofs(dim);
    const std::size_t rotations = dim == 2 ? 1 : 3;
    const auto length = [&](const std::vector<double>& v, const char* name, std::vector<std::size_t> allowed,
                            const std::string& what) {
      if (v.empty()) return;
      if (std::find(allowed.begin(), allowed.end(), v.size()) == allowed.end())
        fail(fmt::format("{}.{} has {} value{}; expected {}", key, name, v.size(), v.size() == 1 ? "" : "s", what));
      for (double x : v)
        if (!std::isfinite(x)) fail(fmt::format("{}.{} holds {}; expected finite numbers", key, name, x));
    };
    const std::string per_dof = fmt::format("{} in a {}D case, one per degree of freedom ({})", dofs.size(), dim,
                                            fmt::join(dofs, ", "));
    length(f.centre_of_gravity, "centre_of_gravity", {static_cast<std::size_t>(dim)},
           fmt::format("{} (a point)", dim));
    length(f.inertia, "inertia", dim == 2 ? std::vector<std::size_t>{1} : std::vector<std::size_t>{3, 6},
           dim == 2 ? "1 in a 2D case, [Izz]" : "3 ([Ixx, Iyy, Izz]) or 6 ([Ixx, Iyy, Izz, Ixy, Ixz, Iyz]) in a 3D case");
    length(f.radius_of_gyration, "radius_of_gyration", {rotations},
           dim == 2 ? "1 in a 2D case, [k]" : "3 in a 3D case, [kx, ky, kz]");
    length(f.angular_velocity, "angular_velocity", {rotations},
           dim == 2 ? "1 in a 2D case, [wz]" : "3 in a 3D case, [wx, wy, wz]");
    length(f.moment, "moment", {rotations}, dim == 2 ? "1 in a 2D case, [Mz]" : "3 in a 3D case, [Mx, My, Mz]");
    length(f.stiffness, "stiffness", {dofs.size()}, per_dof);
    length(f.damping, "damping", {dofs.size()}, per_dof);
    length(f.anchor, "anchor", {dofs.size()}, per_dof);
    if (!f.inertia.empty() && !f.radius_of_gyration.empty())
      fail(fmt::format("{}: both inertia and radius_of_gyration are given; expected one of them (or neither: the "
                       "shape's at uniform density)",
                       key));
    for (std::size_t k = 0; k < f.inertia.size() && k < 3; ++k)
      if (!(f.inertia[k] > 0.0))
        fail(fmt::format("{}.inertia = [{}]: a moment of inertia of {} kg m^2 is not positive; expected each of the "
                         "first {} values > 0",
                         key, fmt::join(f.inertia, ", "), f.inertia[k], std::min<std::size_t>(3, f.inertia.size())));
    if (f.inertia.size() == 6) {
      // A tensor of a real body is positive definite: its leading minors are positive.
      const double xx = f.inertia[0], yy = f.inertia[1], zz = f.inertia[2], xy = f.inertia[3], xz = f.inertia[4],
                   yz = f.inertia[5];
      const double m2 = xx * yy - xy * xy;
      const double m3 = xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
      if (!(m2 > 0.0 && m3 > 0.0))
        fail(fmt::format("{}.inertia = [{}]: not a positive definite tensor; expected a real body's inertia",
                         key, fmt::join(f.inertia, ", ")));
    }
    for (double k : f.radius_of_gyration)
      if (!(k > 0.0))
        fail(fmt::format("{}.radius_of_gyration = [{}]: expected each > 0 m", key, fmt::join(f.radius_of_gyration, ", ")));
    std::set<std::string> locked;
    for (const std::string& name : f.lock) {
      if (std::find(dofs.begin(), dofs.end(), name) == dofs.end())
        fail(fmt::format("{}.lock = {}: {} is not a degree of freedom of a {}D body; expected some of: {}", key,
                         quote(name), quote(name), dim, fmt::join(dofs, ", ")));
      if (!locked.insert(name).second) fail(fmt::format("{}.lock names {} twice; expected each once", key, quote(name)));
    }
    for (std::size_t k = 0; k < f.stiffness.size(); ++k) {
      if (!(f.stiffness[k] >= 0.0))
        fail(fmt::format("{}.stiffness = [{}]: a spring's stiffness is not negative; expected >= 0", key,
                         fmt::join(f.stiffness, ", ")));
      if (f.stiffness[k] > 0.0 && f.anchor.empty())
        fail(fmt::format("{}: the spring on {} (stiffness {}) has no anchor; expected anchor = [...], {} values: "
                         "where each spring is at rest (m, deg)",
                         key, dofs[k], f.stiffness[k], dofs.size()));
    }
    for (double d : f.damping)
      if (!(d >= 0.0))
        fail(fmt::format("{}.damping = [{}]: expected each >= 0", key, fmt::join(f.damping, ", ")));
  }

  // A damping zone: a direction, and a start inside the tank.
  void check_damping() const {
    if (!c.damps()) return;
    double length = 0.0;
    for (int d = 0; d < c.dimension; ++d) length += c.damping_direction[d] * c.damping_direction[d];
    if (!(length > 0.0))
      fail(fmt::format("damping.direction = {}: a vector of length 0; expected the direction into the zone",
                       format_vector(c.damping_direction, c.dimension)));
    const Vec3 tank = c.tank_size();
    std::vector<std::string> extent;
    for (int d = 0; d < c.dimension; ++d) extent.push_back(fmt::format("[0, {}]", tank[d]));
    for (int d = 0; d < c.dimension; ++d)
      if (!(c.damping_start[d] >= 0.0 && c.damping_start[d] <= tank[d]))
        fail(fmt::format("damping.start = {} lies outside the tank {}; expected the start of the zone inside it",
                         format_vector(c.damping_start, c.dimension), fmt::join(extent, " x ")));
  }

  // A wave maker: a piston (a translation) or a flap (a rotation about its hinge, on the floor or
  // above it and below the still water), with the wave's height and the water's depth.
  void check_wave_maker(const MotionLawSpec& m, const std::string& key, bool rotation) const {
    const bool jonswap = m.spectrum == WaveSpectrum::jonswap;
    if (!jonswap && !(m.height > 0.0))
      fail(fmt::format("{}.height = {} m: expected the waves' height, > 0", key, m.height));
    if (!(m.depth > 0.0)) fail(fmt::format("{}.depth = {} m: expected the still water's depth at the piston, > 0", key, m.depth));
    if (m.order != 1 && m.order != 2) fail(fmt::format("{}.order = {}: expected 1 or 2", key, m.order));
    if (jonswap) check_jonswap(m, key);
    if (!rotation) return;
    const double hinge = m.centre[c.dimension - 1];
    if (!(hinge >= 0.0 && hinge < m.depth))
      fail(fmt::format("{}.centre = {}: a flap's hinge {} m above the floor is not in the water; expected a hinge "
                       "from the floor (0) up to below the still water ({} m)",
                       key, format_vector(m.centre, c.dimension), hinge, m.depth));
    if (m.order != 1)
      fail(fmt::format("{}.order = {}: second-order generation is for a piston; expected order = 1 for a flap", key,
                       m.order));
  }

  // An absorbing piston: a wall's translation, horizontal, on water of a given depth; it does not turn.
  void check_absorber(const MotionLawSpec& m, const std::string& key, bool rotation) const {
    const std::string what = m.law == MotionLawType::absorber ? "law = \"absorber\"" : "absorb = true";
    if (key.rfind("tank.", 0) == 0)
      fail(fmt::format("{}.{}: the tank cannot absorb waves; expected a [[wall]] as the absorbing piston inside the "
                       "tank",
                       key, what));
    if (rotation)
      fail(fmt::format("{}.{}: active absorption is for a piston; expected it on the wall's translation (a flap "
                       "cannot absorb)",
                       key, what));
    if (!(m.depth > 0.0)) fail(fmt::format("{}.depth = {} m: expected the still water's depth at the piston, > 0", key, m.depth));
    const int up = c.dimension - 1;
    double length = 0.0;
    for (int d = 0; d < c.dimension; ++d) length += m.direction[d] * m.direction[d];
    if (length > 0.0 && std::abs(m.direction[up]) > 1e-9 * std::sqrt(length))
      fail(fmt::format("{}.direction = {}: an absorbing piston moves horizontally; expected a direction with no "
                       "vertical component, into the water",
                       key, format_vector(m.direction, c.dimension)));
    if (!(m.absorption_time >= 0.0))
      fail(fmt::format("{}.absorption_time = {} s: expected a time > 0, or 0 for the default", key, m.absorption_time));
    if (!(m.absorption_limit >= 0.0))
      fail(fmt::format("{}.absorption_limit = {} m: expected a length > 0, or 0 for the default", key,
                       m.absorption_limit));
  }

  // Irregular waves from a JONSWAP spectrum: its figures in range, first order, a ramp that starts the
  // paddle from rest, and most of the spectrum's energy at wavelengths the particles can carry.
  void check_jonswap(const MotionLawSpec& m, const std::string& key) const {
    if (!(m.significant_height > 0.0))
      fail(fmt::format("{}.significant_height = {} m: expected the significant height Hs of the waves, > 0", key,
                       m.significant_height));
    if (!(m.peak_period > 0.0))
      fail(fmt::format("{}.peak_period = {} s: expected the spectrum's peak period Tp, > 0", key, m.peak_period));
    if (!(m.gamma >= 1.0 && m.gamma <= 10.0))
      fail(fmt::format("{}.gamma = {}: expected the peak enhancement factor from 1 (Pierson-Moskowitz) to 10 (3.3 "
                       "is the JONSWAP mean)",
                       key, m.gamma));
    if (m.components < 1 || m.components > 10000)
      fail(fmt::format("{}.components = {}: expected 1 to 10000 components", key, m.components));
    if (m.seed < 0) fail(fmt::format("{}.seed = {}: expected a seed from 0 to 2147483647", key, m.seed));
    if (m.order != 1)
      fail(fmt::format("{}.order = {}: second-order generation of irregular (JONSWAP) waves is not implemented; "
                       "expected order = 1",
                       key, m.order));
    if (!(m.ramp >= 1.0))
      fail(fmt::format("{}.ramp = {} peak periods: irregular waves start at random phases, the paddle away from "
                       "its rest position; expected a ramp of at least 1 peak period (e.g. 2) to start it from rest",
                       key, m.ramp));
    // A wave shorter than twice the kernel's support (4h) has under one support per half wavelength:
    // the particles cannot carry it.
    const double g = norm(c.gravity) > 0.0 ? norm(c.gravity) : waves::kGravity;
    const double shortest = 4.0 * c.smoothing_length();
    const waves::IrregularSea sea = waves::jonswap_sea(m.significant_height, m.peak_period, m.gamma, m.components,
                                                       static_cast<std::uint64_t>(m.seed));
    const double share = waves::share_longer_than(sea, shortest, m.depth, g);
    if (share < 0.5) {
      const double peak_length =
          2.0 * std::numbers::pi / waves::wavenumber(2.0 * std::numbers::pi / m.peak_period, m.depth, g);
      fail(fmt::format("{}: the JONSWAP spectrum (significant_height = {} m, peak_period = {} s) has little energy in "
                       "the flume's range: {:.1f} % of it at wavelengths of at least 4h = {:.4g} m, the shortest the "
                       "particles carry (domain.dx = {} m), its peak wavelength {:.4g} m; expected at least half of "
                       "it there: a longer peak_period or a smaller domain.dx",
                       key, m.significant_height, m.peak_period, 100.0 * share, shortest, c.dx, peak_length));
    }
  }

  // The set-up fills the tank and its walls (2h each side) with a lattice: a bound on its points keeps
  // a mistyped dx from exhausting memory.
  void check_particle_count() const {
    const double max_points = 5e8;
    const Vec3 tank = c.tank_size();
    double lattice_points = 1.0;
    for (int d = 0; d < c.dimension; ++d) lattice_points *= (tank[d] + 4 * c.smoothing_length()) / c.dx;
    if (lattice_points > max_points)
      fail(fmt::format("domain.dx = {} m gives more than {:.0e} lattice points in the tank; expected a larger dx",
                       c.dx, max_points));
  }
};

}  // namespace

void validate_case(const Case& c, const std::string& source) {
  const Checker check{c, source};
  check.check_name();
  check.check_tank_size();
  check.check_water();
  check.check_walls();
  check.check_bodies();
  check.check_probes();
  check.check_wall_friction();
  check.check_damping();
  if (c.output_formats.empty()) check.fail("output.formats is empty; expected at least one of \"vtk\", \"npz\"");
  check.check_particle_count();
}

}  // namespace sluice
