#include "sluice/geometry/setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "sluice/case/case_error.hpp"
#include "sluice/geometry/box.hpp"
#include "sluice/geometry/floating_body.hpp"
#include "sluice/geometry/lattice.hpp"
#include "sluice/geometry/mesh_solid.hpp"
#include "sluice/geometry/polygon.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/geometry/tank_walls.hpp"
#include "sluice/geometry/wave_theory.hpp"
#include "sluice/physics/eos.hpp"

namespace sluice {

int wall_layers(const Case& c) {
  return std::max(1, static_cast<int>(std::ceil(2.0 * c.smoothing_length() / c.dx - 1e-9)));
}

namespace {

// A box solid. In 2D a box is the 4-point polygon, so that a box and the same polygon given by its
// corners place exactly the same particles.
template <int Dim>
std::shared_ptr<const Solid<Dim>> make_box(const Vec<Dim>& lower, const Vec<Dim>& upper) {
  if constexpr (Dim == 2) return std::make_shared<Polygon>(Polygon::box(lower, upper));
  else return std::make_shared<Box<Dim>>(lower, upper);
}

// A wall slab: the lattice axes of its particles and the box they fill.
template <int Dim>
struct Slab {
  std::array<std::vector<double>, Dim> axes;
  Vec<Dim> lo{}, hi{};

  // Axis a from `from` to `to`, its lattice anchored at `anchor`.
  void span(int a, double anchor, double from, double to, double dx) {
    axes[a] = lattice(anchor, from, to, dx);
    lo[a] = from;
    hi[a] = to;
  }
};

// The tank: a floor slab under everything, the side walls axis by axis, and the lid. Each wall's layers
// are anchored at its own inner face, so the first layer sits dx/2 behind it. The walls across x take
// the whole extent of the other horizontal axis (corners included); the later ones only the inside.
template <int Dim>
void add_tank(Setup<Dim>& s, const Case& c) {
  constexpr int up = Dim - 1;
  const double dx = c.dx;
  const double depth = wall_layers(c) * dx;
  const Vec3 size = c.tank_size();
  const double height = size[up];
  auto add_slab = [&](const Slab<Dim>& slab) {
    for_each_product_point<Dim>(slab.axes, [&](const Vec<Dim>& x) { s.particles.add(x, Kind::wall, c.rest_density); });
    s.solids.push_back(make_box<Dim>(slab.lo, slab.hi));
  };
  Slab<Dim> full;  // the horizontal axes across the side walls
  for (int a = 0; a < up; ++a) full.span(a, 0.0, -depth, size[a] + depth, dx);
  Slab<Dim> floor = full;
  floor.span(up, 0.0, -depth, 0.0, dx);
  add_slab(floor);
  for (int a = 0; a < up; ++a) {
    Slab<Dim> wall = full;
    for (int b = 0; b < a; ++b) wall.span(b, 0.0, 0.0, size[b], dx);
    wall.span(up, 0.0, 0.0, height, dx);
    wall.span(a, 0.0, -depth, 0.0, dx);
    add_slab(wall);
    wall.span(a, size[a], size[a], size[a] + depth, dx);
    add_slab(wall);
  }
  if (c.tank_lid) {
    Slab<Dim> lid = full;
    lid.span(up, height, height, height + depth, dx);
    add_slab(lid);
  }
}

// Water on the lattice (i + 1/2) dx inside the region, outside every solid and at least dx/2 from
// every solid surface (so at least dx from the first wall layer). Returns how many points it placed
// and how many a solid took.
struct Filled {
  std::size_t placed = 0, blocked = 0;
};
template <int Dim>
Filled add_water(Setup<Dim>& s, const Case& c, const Region& r) {
  Filled n;
  const auto region = region_solid<Dim>(r);
  const double tol = 1e-9 * c.dx;
  Vec<Dim> lo = region->lower(), hi = region->upper();
  for (int d = 0; d < Dim; ++d) {
    lo[d] -= tol;
    hi[d] += tol;
  }
  for_each_lattice_point<Dim>(Vec<Dim>{}, lo, hi, c.dx, [&](const Vec<Dim>& p) {
    if (!region->contains(p)) return;
    const bool blocked = std::any_of(s.solids.begin(), s.solids.end(), [&](const auto& q) {
      return q->signed_distance(p) < 0.5 * c.dx - tol;
    });
    if (blocked) {
      ++n.blocked;
      return;
    }
    s.particles.add(p, Kind::fluid, c.rest_density);
    ++n.placed;
  });
  return n;
}

// "box from [0, 0] to [1, 2]", "polygon of 5 points", "mesh column.stl".
std::string describe_region(const Region& r, int dim) {
  const auto point = [dim](const Vec3& v) {
    std::string s = "[";
    for (int d = 0; d < dim; ++d) s += fmt::format("{}{:g}", d > 0 ? ", " : "", v[static_cast<std::size_t>(d)]);
    return s + "]";
  };
  switch (r.shape) {
    case Shape::polygon: return fmt::format("polygon of {} points", r.points.size());
    case Shape::mesh: return fmt::format("mesh {}", std::filesystem::path(r.file).filename().string());
    case Shape::box: break;
  }
  return fmt::format("box from {} to {}", point(r.min), point(r.max));
}

// The region's area (2D) or volume (3D).
template <int Dim>
double region_measure(const Region& r) {
  if constexpr (Dim == 2)
    if (r.shape == Shape::polygon) return Polygon(r.points).area();
  if constexpr (Dim == 3)
    if (r.shape == Shape::mesh && r.mesh != nullptr) return r.mesh->signed_volume();
  double v = 1.0;
  for (int d = 0; d < Dim; ++d) v *= r.max[static_cast<std::size_t>(d)] - r.min[static_cast<std::size_t>(d)];
  return v;
}

// Every water region must hold water; one that the lattice fills with more than 1 % less (or more)
// water than it encloses, and meets no solid, gets a note saying so. Returns the water points placed.
template <int Dim>
std::size_t fill_water(Setup<Dim>& s, const Case& c) {
  std::size_t placed = 0;
  const char* unit = Dim == 2 ? "m^2" : "m^3";
  for (std::size_t k = 0; k < c.water.size(); ++k) {
    const Region& r = c.water[k];
    const Filled n = add_water(s, c, r);
    placed += n.placed;
    const std::string region = fmt::format("[[water]] number {} ({})", k + 1, describe_region(r, Dim));
    if (n.placed == 0)
      throw CaseError(fmt::format(
          "{} holds no water particle at domain.dx = {:g} m: water fills the points (i + 1/2) dx inside a region "
          "that lie at least dx/2 from every wall{}; expected a region at least dx across, or a smaller domain.dx",
          region, c.dx, n.blocked > 0 ? fmt::format(" ({} of its points lie closer to a wall or inside one)", n.blocked)
                                      : ""));
    if (n.blocked > 0) continue;  // its share of the solids' volume is not known here
    const double held = static_cast<double>(n.placed) * std::pow(c.dx, Dim), measure = region_measure<Dim>(r);
    if (measure > 0.0 && std::abs(held / measure - 1.0) > 0.01)
      s.notes.push_back(fmt::format(
          "{}: {} particles hold {:.4g} {} of water, {:.1f} % {} than the region's {:.4g} {}: the particles fill "
          "whole spacings of domain.dx = {:g} m",
          region, n.placed, held, unit, 100.0 * std::abs(held / measure - 1.0), held < measure ? "less" : "more",
          measure, unit, c.dx));
  }
  return placed;
}

// The offsets of Chebyshev length `off` in Dim - 1 horizontal axes, in lexicographic order.
template <int Dim>
std::vector<std::array<long, Dim - 1>> ring(long off) {
  std::vector<std::array<long, Dim - 1>> out;
  std::array<long, Dim - 1> k;
  k.fill(-off);
  while (true) {
    long largest = 0;
    for (long v : k) largest = std::max(largest, std::abs(v));
    if (largest == off) out.push_back(k);
    int d = Dim - 2;
    while (d >= 0 && ++k[d] > off) k[d--] = -off;
    if (d < 0) return out;
  }
}

// The water compressed under its own weight (physics.hydrostatic_squeeze). The lattice places the fluid
// at the spacing of water at rest (rho0), while the hydrostatic start gives it the density of the
// depth; left so, the particles' volumes m / rho do not tile the space they fill, and the discrete
// momentum equation balances gravity with a pressure gradient too steep by about 3 p / (rho0 c0^2)
// (2 % in 1 m of water at c0 = 30 m/s; measured: docs/physics.md, "The initial state"). Squeezed, each contiguous run of
// fluid in a lattice column is moved down onto its lowest point: a particle whose mass coordinate (depth on the lattice) is mu
// moves to the depth D(mu) = int_0^mu rho0 / rho(rho0 g s) ds below the run's compressed top, the
// closed form of the Tait equation. The mass is kept and the bottom stays where it was; the top comes
// down by about g H^2 / (2 c0^2).
template <int Dim, class Column, class ColumnOf>
void compress_columns(Particles<Dim>& p, const Case& c, const std::map<Column, double>& surface, ColumnOf&& column) {
  constexpr int up = Dim - 1;
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  const double a = c.rest_density * -c.gravity[up] / eos.stiffness(), k = 1.0 - 1.0 / c.gamma;
  // ((1 + a mu)^k - 1) / (a k); as k -> 0 (gamma -> 1) it tends to ln(1 + a mu) / a, which
  // expm1(k ln(1 + a mu)) / (a k) reaches without cancellation (at k = 0 the limit itself).
  auto compressed_depth = [&](double mu) {
    if (mu <= 0.0) return mu;
    if (std::abs(k) >= 1e-3) return (std::pow(1.0 + a * mu, k) - 1.0) / (a * k);
    const double log_ratio = std::log1p(a * mu);
    return k == 0.0 ? log_ratio / a : std::expm1(k * log_ratio) / (a * k);
  };
  std::map<Column, std::vector<std::size_t>> columns;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p.is_fluid(i)) columns[column(i)].push_back(i);
  for (auto& [col, members] : columns) {
    std::sort(members.begin(), members.end(), [&](std::size_t i, std::size_t j) { return p.position[up][i] < p.position[up][j]; });
    const double top = surface.at(col);
    std::vector<double> z(members.size());
    for (std::size_t n = 0; n < members.size(); ++n) z[n] = p.position[up][members[n]];
    double bottom = 0.0;  // the lowest edge of the current run, which stays
    for (std::size_t n = 0; n < members.size(); ++n) {
      if (n == 0 || z[n] - z[n - 1] > 1.5 * c.dx) bottom = z[n] - 0.5 * c.dx;
      p.position[up][members[n]] = bottom + compressed_depth(top - bottom) - compressed_depth(top - z[n]);
    }
  }
}

}  // namespace

template <int Dim>
std::shared_ptr<const Solid<Dim>> region_solid(const Region& r) {
  if constexpr (Dim == 2)
    if (r.shape == Shape::polygon) return std::make_shared<Polygon>(r.points);
  if constexpr (Dim == 3)
    if (r.shape == Shape::mesh) {
      if (r.mesh == nullptr) throw std::invalid_argument("a mesh region without its mesh (the case loader reads it)");
      return std::make_shared<MeshSolid>(*r.mesh);
    }
  return make_box<Dim>(first<Dim>(r.min), first<Dim>(r.max));
}

template <int Dim>
std::size_t remove_near_coincident(Particles<Dim>& p, double min_distance, const std::vector<std::uint8_t>& moving) {
  const auto moves = [&](std::uint8_t body) { return body < moving.size() && moving[body] != 0; };
  const std::size_t n = p.size();
  if (n == 0) return 0;
  Vec<Dim> lo{}, hi{};
  for (int d = 0; d < Dim; ++d) lo[d] = hi[d] = p.position[d][0];
  for (std::size_t i = 0; i < n; ++i)
    for (int d = 0; d < Dim; ++d) {
      lo[d] = std::min(lo[d], p.position[d][i]);
      hi[d] = std::max(hi[d], p.position[d][i]);
    }
  // Cells of twice the distance: a neighbour within it is in an adjacent cell, and the cell array stays
  // small over the air of a mostly empty tank.
  CellGrid<Dim> grid(lo, hi, 2.0 * min_distance);
  grid.bin(p.position);
  const auto& order = grid.order();  // sorted index k holds particle order[k]
  std::vector<std::uint8_t> removed(n, 0);
  const double min2 = min_distance * min_distance;
  // Visit walls first so that a wall point always wins over a fluid point; otherwise the lower index wins.
  for (Kind pass : {Kind::wall, Kind::fluid}) {
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t i = order[k];
      if (p.kind[i] != pass || removed[i]) continue;
      grid.for_each_neighbor_range(grid.cell_of()[k], [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t kj = begin; kj < end; ++kj) {
          const std::uint32_t j = order[kj];
          if (j == i || removed[j]) continue;
          if (p.kind[j] == Kind::wall && pass == Kind::fluid) continue;
          if (p.kind[j] == pass && j < i) continue;
          // A moving body's walls may touch another's (a gate standing on the floor): each keeps its own
          // particles. Fixed walls that overlap are thinned as one.
          if (pass == Kind::wall && p.kind[j] == Kind::wall && p.body[j] != p.body[i] &&
              (moves(p.body[i]) || moves(p.body[j])))
            continue;
          double r2 = 0.0;
          for (int d = 0; d < Dim; ++d) {
            const double delta = p.position[d][i] - p.position[d][j];
            r2 += delta * delta;
          }
          if (r2 < min2) removed[j] = 1;
        }
      });
    }
  }
  std::vector<std::uint32_t> keep;
  for (std::uint32_t i = 0; i < n; ++i)
    if (!removed[i]) keep.push_back(i);
  p.keep_only(keep);
  return n - keep.size();
}

template <int Dim>
void set_hydrostatic_density(Particles<Dim>& p, const Case& c) {
  constexpr int up = Dim - 1;
  const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
  const double g = -c.gravity[up];
  if (g <= 0.0) return;
  using Column = std::array<long, Dim - 1>;
  auto column = [&](std::size_t i) {
    Column k{};
    for (int a = 0; a < up; ++a) k[a] = static_cast<long>(std::floor(p.position[a][i] / c.dx));
    return k;
  };
  // Free-surface height over each lattice column: top of the highest fluid particle in it.
  std::map<Column, double> surface;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) continue;
    const double top = p.position[up][i] + 0.5 * c.dx;
    auto [it, inserted] = surface.emplace(column(i), top);
    if (!inserted) it->second = std::max(it->second, top);
  }
  if (surface.empty()) return;
  // Walls beside the water take the nearest column's surface.
  const long reach = wall_layers(c) + 1;
  std::vector<std::vector<Column>> rings;
  for (long off = 1; off <= reach; ++off) rings.push_back(ring<Dim>(off));
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Column col = column(i);
    auto it = surface.find(col);
    for (const auto& offsets : rings) {
      for (const Column& o : offsets) {
        if (it != surface.end()) break;
        Column near = col;
        for (int a = 0; a < up; ++a) near[a] += o[a];
        it = surface.find(near);
      }
      if (it != surface.end()) break;
    }
    if (it == surface.end()) continue;
    const double depth = it->second - p.position[up][i];
    if (depth > 0.0) p.density[i] = eos.density(c.rest_density * g * depth);
  }
  if (c.hydrostatic_squeeze) compress_columns(p, c, surface, column);
}

template <int Dim>
std::shared_ptr<const Solid<Dim>> box_solid(const Vec<Dim>& lower, const Vec<Dim>& upper) {
  return make_box<Dim>(lower, upper);
}

// The breaking warnings of a wave maker: past Miche's steepness 0.142 tanh kh, or past the
// depth-limited height H/h = 0.78; `words` name the ratios (H/L or Hs/Lp) and what breaks.
struct BreakingWords {
  const char* steepness;
  const char* depth_ratio;
  const char* breaks;
};
void add_breaking_warnings(std::vector<std::string>& notes, const std::string& key, const waves::RegularWave& w,
                           double height_over_depth, const BreakingWords& words) {
  if (w.steepness > w.miche_steepness)
    notes.push_back(fmt::format("warning: {}: {} = {:.4f} is past Miche's breaking limit 0.142 tanh(kh) = {:.4f}{}", key,
                                words.steepness, w.steepness, w.miche_steepness, words.breaks));
  if (height_over_depth > 0.78)
    notes.push_back(fmt::format("warning: {}: {} = {:.3f} is past the depth-limited breaking limit 0.78", key,
                                words.depth_ratio, height_over_depth));
}

// What an irregular wave maker will make: its spectrum's figures, the peak wave's length, kh and
// steepness Hs/Lp, the band and when the waves repeat, the paddle's stroke (its rms and 4 rms, the
// stroke's significant value), the energy too short for the particles; and the regular maker's
// breaking warnings for the significant wave (the highest waves of a sea are about twice as high).
void add_jonswap_notes(std::vector<std::string>& notes, const Case& c, const MotionLawSpec& m, const std::string& key,
                       bool rotation, double g) {
  const waves::IrregularSea sea =
      waves::jonswap_sea(m.significant_height, m.peak_period, m.gamma, m.components, static_cast<std::uint64_t>(m.seed));
  const waves::RegularWave peak = waves::regular_wave(m.significant_height, m.peak_period, m.depth, g);
  const double hinge = m.centre[c.dimension - 1];
  double stroke_variance = 0.0;
  for (const waves::WaveComponent& component : sea.components) {
    const double k = waves::wavenumber(2.0 * std::numbers::pi * component.frequency, m.depth, g);
    const double per_stroke =
        rotation ? waves::flap_height_per_stroke(k, m.depth, hinge) : waves::piston_height_per_stroke(k * m.depth);
    const double x = m.gain * component.amplitude / per_stroke;
    stroke_variance += 0.5 * x * x;
  }
  const double stroke_rms = std::sqrt(stroke_variance);
  const double fp = sea.peak_frequency;
  std::string note = fmt::format(
      "{}: {} waves from a JONSWAP spectrum Hs = {:.4g} m, Tp = {:.4g} s, gamma = {:.3g} on h = {:.4g} m: peak "
      "wavelength {:.4g} m, kh = {:.3f} at the peak, Hs/Lp = {:.4f}; {} components from {:.3g} to {:.3g} fp, df = "
      "{:.4g} Hz (seed {}), {:.1f} % of the spectrum in the band; the waves repeat every {:.4g} s; stroke rms "
      "{:.4g} m, 4 rms {:.4g} m at the still-water level",
      key, rotation ? "flap" : "piston", m.significant_height, m.peak_period, m.gamma, m.depth, peak.wavelength,
      peak.kh, peak.steepness, sea.components.size(), sea.components.front().frequency / fp,
      sea.components.back().frequency / fp, sea.df, m.seed, 100.0 * sea.band_share, 1.0 / sea.df, stroke_rms,
      4.0 * stroke_rms);
  if (rotation)
    note += fmt::format(" (hinge {:.4g} m above the floor, angle rms about {:.4g} deg)", hinge,
                        std::atan(stroke_rms / (m.depth - hinge)) * 180.0 / std::numbers::pi);
  const double shortest = 4.0 * c.smoothing_length();
  const double short_share = 1.0 - waves::share_longer_than(sea, shortest, m.depth, g);
  if (short_share > 0.01)
    note += fmt::format("; {:.1f} % of the energy at wavelengths under 4h = {:.4g} m, too short for the particles",
                        100.0 * short_share, shortest);
  notes.push_back(note);
  add_breaking_warnings(notes, key, peak, m.significant_height / m.depth, {"Hs/Lp", "Hs/h", " at the peak: the significant wave breaks"});
}

// What a wave maker will make, by linear theory: the wave's length, kh, steepness and the stroke
// that makes it; and a warning where the wave lies past a breaking limit (Miche's steepness
// 0.142 tanh kh, or H/h > 0.78) or, for second order, where Stokes' second-order theory fails
// (the Ursell number H L^2 / h^3 above 8 pi^2 / 3, where the second harmonic exceeds a quarter of
// the first).
void add_wave_maker_notes(std::vector<std::string>& notes, const Case& c) {
  const double g = norm(c.gravity);
  if (!(g > 0.0)) return;
  for_each_motion_law(c, [&](const MotionLawSpec& m, const std::string& key, bool rotation) {
    if (m.law != MotionLawType::wave) return;
    if (m.spectrum == WaveSpectrum::jonswap) return add_jonswap_notes(notes, c, m, key, rotation, g);
    const waves::RegularWave w = waves::regular_wave(m.height, m.period, m.depth, g);
    const double hinge = m.centre[c.dimension - 1];
    const double stroke = m.gain * m.height /
                          (rotation ? waves::flap_height_per_stroke(w.k, m.depth, hinge) : waves::piston_height_per_stroke(w.kh));
    std::string note = fmt::format(
        "{}: {} waves H = {:.4g} m, T = {:.4g} s on h = {:.4g} m: wavelength {:.4g} m, kh = {:.3f}, H/L = "
        "{:.4f}, celerity {:.4g} m/s, group velocity {:.4g} m/s; stroke {:.4g} m at the still-water level",
        key, rotation ? "flap" : "piston", m.height, m.period, m.depth, w.wavelength, w.kh, w.steepness, w.celerity,
        w.group_velocity, stroke);
    if (rotation)
      note += fmt::format(" (hinge {:.4g} m above the floor, angle amplitude {:.4g} deg)", hinge,
                          std::atan(0.5 * stroke / (m.depth - hinge)) * 180.0 / std::numbers::pi);
    else
      note += fmt::format(" (order {})", m.order);
    if (m.order == 2)
      note += fmt::format(", second-order amplitude {:.3g} m", m.gain * waves::madsen_second_order_amplitude(m.height, w.k, m.depth));
    notes.push_back(note);
    add_breaking_warnings(notes, key, w, m.height / m.depth, {"H/L", "H/h", ": such a wave breaks"});
    if (m.order == 2 && w.ursell > 8.0 * std::numbers::pi * std::numbers::pi / 3.0)
      notes.push_back(fmt::format("warning: {}: the Ursell number H L^2/h^3 = {:.3g} is above 8 pi^2/3 = 26.3, where "
                                  "second-order (Stokes) theory does not hold; the piston's second-order motion is "
                                  "not the wave's",
                                  key, w.ursell));
  });
}

// What each floating body is (its mass, centre of gravity and inertia, as the solver takes them), and
// a warning for one denser than the water: it sinks (a valid case, but rarely the one meant).
void add_floating_notes(std::vector<std::string>& notes, const Case& c) {
  for (std::size_t k = 0; k < c.walls.size(); ++k) {
    const Region& w = c.walls[k];
    if (!w.floats) continue;
    const MassProperties shape = mass_properties(w, c.dimension);
    const FloatingModel m = floating_model(w.floating, shape, c.dimension, c.gravity);
    const bool plane = c.dimension == 2;
    std::string centre, inertia;
    for (int d = 0; d < c.dimension; ++d) centre += fmt::format("{}{:.4g}", d ? ", " : "", m.start_centre[d]);
    if (plane) inertia = fmt::format("{:.4g}", m.inertia[2]);
    else inertia = fmt::format("{:.4g}, {:.4g}, {:.4g}", m.inertia[0], m.inertia[1], m.inertia[2]);
    const double density = m.mass / shape.volume;
    notes.push_back(fmt::format("wall[{}] ({}) floats: mass {:.4g} kg{}, mean density {:.4g} kg/m^3, centre of gravity "
                                "({}) m, inertia {} kg m^2{}",
                                k, w.name, m.mass, plane ? "/m" : "", density, centre, inertia, plane ? "/m" : ""));
    if (density > c.rest_density)
      notes.push_back(fmt::format("warning: wall[{}] ({}) floats with a mean density of {:.4g} kg/m^3, above the "
                                  "water's {:.4g}: it will sink",
                                  k, w.name, density, c.rest_density));
  }
}

template <int Dim>
Setup<Dim> build_setup(const Case& c) {
  Setup<Dim> s;
  add_tank(s, c);
  if (c.tank_moves()) {
    // A moving tank is one body: its slabs become one solid, the outside of its inside.
    s.solids.clear();
    Vec<Dim> size{};
    for (int d = 0; d < Dim; ++d) size[d] = c.tank_size()[d];
    s.solids.push_back(std::make_shared<TankWalls<Dim>>(size, c.tank_lid, wall_layers(c) * c.dx));
  }
  const int layers = wall_layers(c);
  for (std::size_t k = 0; k < c.walls.size(); ++k) {
    const auto solid = region_solid<Dim>(c.walls[k]);
    const auto body = static_cast<std::uint8_t>(body_id::first_wall + k);
    solid->fill_surface_layers(c.dx, layers, [&](const Vec<Dim>& x) { s.particles.add(x, Kind::wall, c.rest_density, body); });
    s.solids.push_back(solid);
  }
  const std::size_t placed = fill_water(s, c);
  std::vector<std::uint8_t> moving(body_id::first_wall + c.walls.size(), 0);
  moving[body_id::tank] = c.tank_moves();
  for (std::size_t k = 0; k < c.walls.size(); ++k) moving[body_id::first_wall + k] = c.walls[k].moves();
  s.removed_near_coincident = remove_near_coincident(s.particles, 0.5 * c.dx, moving);
  // Water thinned is water the case asked for; wall points thinned (where a solid's layers meet inside
  // it) are the wall filling's own business.
  std::size_t fluid = 0;
  for (std::size_t i = 0; i < s.particles.size(); ++i) fluid += s.particles.is_fluid(i) ? 1 : 0;
  if (const std::size_t water = placed - fluid; water > 0)
    s.notes.push_back(fmt::format("{} water particles removed at set-up, each closer than dx/2 to a point that was "
                                  "kept (where water regions overlap, or water lies on a wall particle)",
                                  water));
  add_wave_maker_notes(s.notes, c);
  add_floating_notes(s.notes, c);
  if (c.hydrostatic_start) set_hydrostatic_density(s.particles, c);
  if (c.initial_pressure != 0.0) {
    const TaitEos eos{c.rest_density, c.sound_speed, c.gamma};
    const double floor = -0.99 * eos.stiffness();  // the lowest pressure the Tait equation can represent
    for (std::size_t i = 0; i < s.particles.size(); ++i)
      if (s.particles.is_fluid(i))
        s.particles.density[i] = eos.density(std::max(eos.pressure(s.particles.density[i]) + c.initial_pressure, floor));
  }
  return s;
}

#define SLUICE_INSTANTIATE(Dim)                                                      \
  template std::shared_ptr<const Solid<Dim>> region_solid<Dim>(const Region&);       \
  template Setup<Dim> build_setup<Dim>(const Case&);                                 \
  template std::shared_ptr<const Solid<Dim>> box_solid<Dim>(const Vec<Dim>&, const Vec<Dim>&); \
  template std::size_t remove_near_coincident<Dim>(Particles<Dim>&, double, const std::vector<std::uint8_t>&); \
  template void set_hydrostatic_density<Dim>(Particles<Dim>&, const Case&);
SLUICE_INSTANTIATE(2)
SLUICE_INSTANTIATE(3)
#undef SLUICE_INSTANTIATE

}  // namespace sluice
