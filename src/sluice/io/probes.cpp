#include "sluice/io/probes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "sluice/io/atomic_file.hpp"

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

template <int Dim>
std::vector<double> pressure_at(const Probe& probe, const Solver<Dim>& solver) {
  const Particles<Dim>& p = solver.particles();
  const Vec<Dim> at = first<Dim>(probe.point);
  return std::visit(
      [&](const auto& kernel) -> std::vector<double> {
        const double support = std::decay_t<decltype(kernel)>::support * kernel.h;
        double weighted = 0.0, weight = 0.0;
        std::int64_t neighbours = 0;
        Vec<Dim> lower = at, upper = at;
        for (int d = 0; d < Dim; ++d) lower[d] -= support, upper[d] += support;
        solver.for_each_range_in_box(lower, upper, [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t i = begin; i < end; ++i) {
            if (!p.is_fluid(i)) continue;
            double r2 = 0.0;
            for (int d = 0; d < Dim; ++d) {
              const double r = p.position[d][i] - at[d];
              r2 += r * r;
            }
            if (r2 >= support * support) continue;
            const double w = kernel.value(std::sqrt(r2)) * solver.particle_mass() / p.density[i];
            weighted += w * solver.eos().pressure(p.density[i]);
            weight += w;
            ++neighbours;
          }
        });
        const Reducer& all = solver.reducer();
        weighted = all.sum(weighted);
        weight = all.sum(weight);
        return {weight > 0.0 ? weighted / weight : 0.0, static_cast<double>(all.sum(neighbours))};
      },
      solver.kernel());
}

template <int Dim>
std::vector<double> gauge_height(const Probe& probe, const Solver<Dim>& solver) {
  constexpr int up = Dim - 1;
  const Particles<Dim>& p = solver.particles();
  const double dx = solver.config().dx;
  const double band = probe.band > 0.0 ? probe.band : dx;
  Vec<Dim> lower{}, upper{};
  for (int d = 0; d < up; ++d) {
    lower[d] = probe.point[d] - band;
    upper[d] = probe.point[d] + band;
  }
  lower[up] = -std::numeric_limits<double>::infinity();  // the whole column (clamped to the grid)
  upper[up] = std::numeric_limits<double>::infinity();
  double top = -std::numeric_limits<double>::infinity();
  solver.for_each_range_in_box(lower, upper, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = begin; i < end; ++i) {
      if (!p.is_fluid(i)) continue;
      bool inside = true;
      for (int d = 0; d < up; ++d) inside = inside && std::abs(p.position[d][i] - probe.point[d]) <= band;
      if (!inside) continue;
      const double y = p.position[up][i] + 0.5 * dx;
      top = std::max(top, y);
    }
  });
  top = solver.reducer().max(top);
  return {std::isinf(top) ? 0.0 : top};
}

// The furthest fluid particle along the direction; of several equally far, the one of lowest index.
template <int Dim>
std::vector<double> front_position(const Probe& probe, const Solver<Dim>& solver) {
  const Particles<Dim>& p = solver.particles();
  const Vec<Dim> origin = first<Dim>(probe.point);
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
                             double keep_until, bool fresh) {
  if (probes.empty()) return;
  create_directories_or_throw(dir);
  for (const Probe& probe : probes) {
    const auto path = dir / (probe.name + ".csv");
    Series s{probe, AppendFile(path, probe_header(probe, dimension) + "\n"), "", 0};
    std::error_code ec;
    if (!fresh && std::filesystem::exists(path, ec)) s.file.resume(csv_rows_until(read_file(path), keep_until));
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
    s.rows += fmt::format("{}", t);
    for (double v : sample_probe(s.probe, sim)) s.rows += fmt::format(",{}", v);
    s.rows += "\n";
  }
}

void ProbeRecorder::flush() {
  for (Series& s : series_) {
    s.file.append(s.rows);
    s.rows.clear();
  }
}

void ProbeRecorder::sync() {
  for (Series& s : series_) s.file.sync();
}

}  // namespace sluice
