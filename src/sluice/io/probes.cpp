#include "sluice/io/probes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "sluice/core/body_id.hpp"
#include "sluice/core/linear_fit.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/solver/free_surface.hpp"

namespace sluice {

std::string probe_header(const Probe& probe, int dimension) {
  switch (probe.type) {
    case ProbeType::pressure: return "time,pressure,neighbours";
    case ProbeType::gauge: return "time,height";
    case ProbeType::front: return dimension == 3 ? "time,distance,x,y,z" : "time,distance,x,y";
  }
  return "";
}

namespace {

// The pressure interpolated at x from the particles within the kernel support: the fluid's, and the
// wall particles' where the wall treatment gives them the wall's pressure (Adami, mDBC). Shepard: the
// kernel average normalised by its weights. Linear: the first-order fit of core/linear_fit.hpp to the
// neighbours' pressures with the weights V_j W_ij (exact for a linear pressure field, hydrostatic
// pressure included, even where the neighbours lie on one side, as at a wall); Shepard where the fit
// is ill-posed (fewer neighbours than unknowns, or in a line). `neighbours` counts the particles used. No neighbours: 0.
template <int Dim, class Kernel>
double interpolated_pressure(const Solver<Dim>& solver, const Kernel& kernel, const Vec<Dim>& at,
                             ProbeCorrection correction, bool with_walls, std::int64_t& neighbours) {
  const Particles<Dim>& p = solver.particles();
  const double support = Kernel::support * kernel.h, inv_h = 1.0 / kernel.h;
  LinearFit<Dim> fit;
  neighbours = 0;
  Vec<Dim> lower = at, upper = at;
  for (int d = 0; d < Dim; ++d) lower[d] -= support, upper[d] += support;
  solver.for_each_range_in_box(lower, upper, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = begin; i < end; ++i) {
      if (!p.is_fluid(i) && !with_walls) continue;
      std::array<double, Dim> y{};
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        const double r = p.position[d][i] - at[d];
        r2 += r * r;
        y[d] = r * inv_h;
      }
      if (r2 >= support * support) continue;
      const double w = kernel.value(std::sqrt(r2)) * solver.particle_mass() / p.density[i];
      fit.add(w, y, solver.eos().pressure(p.density[i]));
      ++neighbours;
    }
  });
  // Every process's neighbours (the fit is over all of them).
  const Reducer& all = solver.reducer();
  for (int a = 0; a < LinearFit<Dim>::M; ++a) {
    fit.rhs[a] = all.sum(fit.rhs[a]);
    for (int b = 0; b < LinearFit<Dim>::M; ++b) fit.moments[a][b] = all.sum(fit.moments[a][b]);
  }
  neighbours = all.sum(neighbours);
  if (!(fit.weight() > 0.0)) return 0.0;
  if (correction == ProbeCorrection::shepard || neighbours < LinearFit<Dim>::M) return fit.shepard();
  const auto coef = fit.solve();
  return coef ? (*coef)[0] : fit.shepard();
}

// Where a pressure sensor of diameter `size` centred at `at` samples: points about dx/4 apart over a
// segment (2D) or a disc (3D) in the tangent plane of the nearest solid surface; the centre alone for
// a point probe or when no solid is near.
template <int Dim>
std::vector<Vec<Dim>> sensor_points(const Solver<Dim>& solver, const Vec<Dim>& at, double size) {
  std::vector<Vec<Dim>> points{at};
  if (!(size > 0.0) || solver.solids().empty()) return points;
  double nearest = std::numeric_limits<double>::infinity();
  Vec<Dim> normal{};
  for (const auto& solid : solver.solids()) {
    const double distance = std::abs(solid->signed_distance(at));
    if (distance < nearest) {
      nearest = distance;
      normal = solid->closest_surface_point(at).normal;
    }
  }
  // Two (in 3D) or one (in 2D) unit tangents.
  std::array<Vec<Dim>, Dim - 1> tangent{};
  if constexpr (Dim == 2) {
    tangent[0] = Vec<Dim>{-normal[1], normal[0]};
  } else {
    const Vec<Dim> helper = std::abs(normal[0]) < 0.9 ? Vec<Dim>{1.0, 0.0, 0.0} : Vec<Dim>{0.0, 1.0, 0.0};
    const Vec<Dim> t0 = helper - dot(helper, normal) * normal;
    tangent[0] = (1.0 / norm(t0)) * t0;
    tangent[1] = Vec<Dim>{normal[1] * tangent[0][2] - normal[2] * tangent[0][1],
                          normal[2] * tangent[0][0] - normal[0] * tangent[0][2],
                          normal[0] * tangent[0][1] - normal[1] * tangent[0][0]};
  }
  const double spacing = 0.25 * solver.config().dx;
  const int half = std::max(1, static_cast<int>(std::ceil(0.5 * size / spacing)));
  const double step = 0.5 * size / half;
  points.clear();
  if constexpr (Dim == 2) {
    for (int k = -half; k <= half; ++k) points.push_back(at + (k * step) * tangent[0]);
  } else {
    for (int k = -half; k <= half; ++k)
      for (int l = -half; l <= half; ++l)
        if ((k * k + l * l) * step * step <= 0.25 * size * size * (1.0 + 1e-12))
          points.push_back(at + (k * step) * tangent[0] + (l * step) * tangent[1]);
  }
  return points;
}

// Where the probe's point is now: where the case puts it, or, for a probe that moves with a wall, that
// point carried by the wall's motion.
template <int Dim>
Vec<Dim> probe_point(const Probe& probe, const Solver<Dim>& solver) {
  const Vec<Dim> at = first<Dim>(probe.point);
  if (probe.wall.empty()) return at;
  for (const auto& body : solver.bodies().list())
    if ((body.id >= body_id::first_wall || (body.id == body_id::tank && body.moves)) && body.name == probe.wall)
      return solver.bodies().carried(body.id, at);
  throw std::logic_error("probe_point: the probe's wall is not a body of the run");
}

template <int Dim>
std::vector<double> pressure_at(const Probe& probe, const Solver<Dim>& solver) {
  const Vec<Dim> at = probe_point<Dim>(probe, solver);
  const bool with_walls = solver.config().wall_boundary != WallBoundary::dynamic;
  const std::vector<Vec<Dim>> points = sensor_points<Dim>(solver, at, probe.size);
  return std::visit(
      [&](const auto& kernel) -> std::vector<double> {
        // The mean over the sensor's points; a point without water reads 0.
        double sum = 0.0;
        std::int64_t centre_neighbours = 0;
        for (std::size_t k = 0; k < points.size(); ++k) {
          std::int64_t neighbours = 0;
          sum += interpolated_pressure<Dim>(solver, kernel, points[k], probe.correction, with_walls, neighbours);
          if (k == points.size() / 2) centre_neighbours = neighbours;
        }
        return {sum / static_cast<double>(points.size()), static_cast<double>(centre_neighbours)};
      },
      solver.kernel());
}

// The fluid particles in a gauge's band: f(height of the particle's top) for each.
template <int Dim, class F>
void for_each_in_band(const Probe& probe, const Solver<Dim>& solver, F&& f) {
  constexpr int up = Dim - 1;
  const Particles<Dim>& p = solver.particles();
  const double dx = solver.config().dx;
  const double band = probe.band > 0.0 ? probe.band : dx;
  const Vec<Dim> point = probe_point<Dim>(probe, solver);
  Vec<Dim> lower{}, upper{};
  for (int d = 0; d < up; ++d) {
    lower[d] = point[d] - band;
    upper[d] = point[d] + band;
  }
  lower[up] = -std::numeric_limits<double>::infinity();  // the whole column (clamped to the grid)
  upper[up] = std::numeric_limits<double>::infinity();
  solver.for_each_range_in_box(lower, upper, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = begin; i < end; ++i) {
      if (!p.is_fluid(i)) continue;
      bool inside = true;
      for (int d = 0; d < up; ++d) inside = inside && std::abs(p.position[d][i] - point[d]) <= band;
      if (inside) f(p.position[up][i] + 0.5 * dx);
    }
  });
}

// The top of the water standing on the gauge's foot (point[up]): the band is cut into slices one
// particle spacing high, a particle in the slice of its centre, and the water is the run of occupied
// slices from the foot (its first within two slices of it) up to the first two empty slices in a
// row; its level is the top of the highest particle in the run. Each slice's highest top is reduced
// over processes, so that the run is found on the whole column. 0 when no water stands there.
template <int Dim>
double column_top(const Probe& probe, const Solver<Dim>& solver) {
  constexpr int up = Dim - 1;
  const double dx = solver.config().dx, foot = probe_point<Dim>(probe, solver)[up];
  double highest = -std::numeric_limits<double>::infinity();
  for_each_in_band(probe, solver, [&](double top) { highest = std::max(highest, top); });
  highest = solver.reducer().max(highest);
  if (!(highest - 0.5 * dx >= foot)) return 0.0;
  const auto slices = static_cast<std::size_t>((highest - 0.5 * dx - foot) / dx) + 1;
  std::vector<double> slice_top(slices, -std::numeric_limits<double>::infinity());
  for_each_in_band(probe, solver, [&](double top) {
    const double above = top - 0.5 * dx - foot;
    if (above < 0.0) return;
    const auto k = std::min(slices - 1, static_cast<std::size_t>(above / dx));
    slice_top[k] = std::max(slice_top[k], top);
  });
  slice_top = solver.reducer().max(std::move(slice_top));
  double level = 0.0;
  std::size_t empty = 0;
  for (std::size_t k = 0; k < slices; ++k) {
    if (std::isinf(slice_top[k])) {
      if (++empty >= 2) break;
      continue;
    }
    empty = 0;
    level = slice_top[k];
  }
  return level;
}

template <int Dim>
std::vector<double> gauge_height(const Probe& probe, const Solver<Dim>& solver) {
  if (probe.measure == GaugeMeasure::column) return {column_top(probe, solver)};
  if (probe.measure == GaugeMeasure::surface) return {kernel_surface<Dim>(solver, probe_point<Dim>(probe, solver))};
  double top = -std::numeric_limits<double>::infinity();
  for_each_in_band(probe, solver, [&](double t) { top = std::max(top, t); });
  top = solver.reducer().max(top);
  return {std::isinf(top) ? 0.0 : top};
}

// The furthest fluid particle along the direction; of several equally far, the one of lowest index.
template <int Dim>
std::vector<double> front_position(const Probe& probe, const Solver<Dim>& solver) {
  const Particles<Dim>& p = solver.particles();
  const Vec<Dim> origin = probe_point<Dim>(probe, solver);
  const Vec<Dim> dir = (1.0 / norm(first<Dim>(probe.direction))) * first<Dim>(probe.direction);
  double best = -std::numeric_limits<double>::infinity();
  Vec<Dim> at{};
  for (std::size_t i = 0; i < p.owned(); ++i) {
    if (!p.is_fluid(i)) continue;
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = p.position[d][i];
    const double s = dot(x - origin, dir);
    if (s > best) {
      best = s;
      at = x;
    }
  }
  std::vector<double> out{best};
  out.insert(out.end(), at.begin(), at.end());
  return solver.reducer().payload_of_max(best, out);
}

}  // namespace

std::vector<double> sample_probe(const Probe& probe, const Simulation& sim) {
  return sim.visit([&](const auto& solver) {
    switch (probe.type) {
      case ProbeType::pressure: return pressure_at(probe, solver);
      case ProbeType::gauge: return gauge_height(probe, solver);
      case ProbeType::front: break;
    }
    return front_position(probe, solver);
  });
}

std::string csv_rows_until(const std::string& csv, double t_max) {
  std::size_t end = csv.find('\n');
  if (end == std::string::npos) return "";
  std::size_t kept = end + 1;  // the header
  for (; (end = csv.find('\n', kept)) != std::string::npos; kept = end + 1) {
    const std::string line = csv.substr(kept, end - kept);
    double t = 0.0;
    try {
      t = std::stod(line.substr(0, line.find(',')));
    } catch (const std::exception&) {
      break;  // a malformed row: keep what came before
    }
    if (t > t_max * (1.0 + 1e-12) + 1e-300) break;
  }
  return csv.substr(0, kept);
}

ProbeRecorder::ProbeRecorder(const std::vector<Probe>& probes, int dimension, const std::filesystem::path& dir,
                             double keep_until, bool fresh, bool writes)
    : writes_(writes) {
  if (probes.empty()) return;
  if (writes_) create_directories_or_throw(dir);
  for (const Probe& probe : probes) {
    const auto path = dir / (probe.name + ".csv");
    Series s{probe, AppendFile(path, probe_header(probe, dimension) + "\n"), "", 0};
    std::error_code ec;
    if (writes_ && !fresh && std::filesystem::exists(path, ec)) s.file.resume(csv_rows_until(read_file(path), keep_until));
    if (probe.interval > 0.0) s.next_sample = static_cast<std::int64_t>(std::floor(keep_until / probe.interval + 1e-9)) + (fresh ? 0 : 1);
    series_.push_back(std::move(s));
  }
}

void ProbeRecorder::sample(const Simulation& sim) {
  const double t = sim.time();
  for (Series& s : series_) {
    if (s.probe.interval > 0.0) {
      if (t + 1e-12 * s.probe.interval < static_cast<double>(s.next_sample) * s.probe.interval) continue;
      s.next_sample = static_cast<std::int64_t>(std::floor(t / s.probe.interval + 1e-9)) + 1;
    }
    const std::vector<double> values = sample_probe(s.probe, sim);  // collective
    if (!writes_) continue;
    s.rows += fmt::format("{}", t);
    for (double v : values) s.rows += fmt::format(",{}", v);
    s.rows += "\n";
  }
}

void ProbeRecorder::flush() {
  if (!writes_) return;
  for (Series& s : series_) {
    s.file.append(s.rows);
    s.rows.clear();
  }
}

void ProbeRecorder::sync() {
  if (!writes_) return;
  for (Series& s : series_) s.file.sync();
}

}  // namespace sluice
