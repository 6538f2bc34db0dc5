#include "sluice/io/probes.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "sluice/io/atomic_file.hpp"

namespace sluice {

std::string probe_header(const Probe& probe) {
  if (probe.type == "pressure") return "time,pressure,neighbours";
  if (probe.type == "gauge") return "time,height";
  return "time,distance,x,y";
}

std::vector<double> sample_probe(const Probe& probe, const Simulation& sim) {
  const Particles<2>& p = sim.particles();
  const double dx = sim.config().dx;
  if (probe.type == "pressure") {
    const CubicSpline<2> kernel(sim.smoothing_length());
    const double support2 = 4.0 * kernel.h * kernel.h;
    double weighted = 0.0, weight = 0.0;
    int neighbours = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!p.is_fluid(i)) continue;
      const double rx = p.position[0][i] - probe.point[0];
      const double ry = p.position[1][i] - probe.point[1];
      const double r2 = rx * rx + ry * ry;
      if (r2 >= support2) continue;
      const double w = kernel.value(std::sqrt(r2)) * sim.particle_mass() / p.density[i];
      weighted += w * sim.eos().pressure(p.density[i]);
      weight += w;
      ++neighbours;
    }
    return {weight > 0.0 ? weighted / weight : 0.0, static_cast<double>(neighbours)};
  }
  if (probe.type == "gauge") {
    const double band = probe.band > 0.0 ? probe.band : dx;
    double top = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (!p.is_fluid(i) || std::abs(p.position[0][i] - probe.point[0]) > band) continue;
      const double y = p.position[1][i] + 0.5 * dx;
      if (!(top >= y)) top = y;
    }
    return {std::isnan(top) ? 0.0 : top};
  }
  const Vec2 dir = (1.0 / norm(probe.direction)) * probe.direction;
  double best = -std::numeric_limits<double>::infinity();
  Vec2 at{0.0, 0.0};
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!p.is_fluid(i)) continue;
    const Vec2 x{p.position[0][i], p.position[1][i]};
    const double s = dot(x - probe.point, dir);
    if (s > best) {
      best = s;
      at = x;
    }
  }
  return {best, at[0], at[1]};
}

std::string csv_rows_until(const std::string& csv, double t_max) {
  std::istringstream in(csv);
  std::string line, out;
  bool header = true;
  while (std::getline(in, line)) {
    if (header) {
      out += line + "\n";
      header = false;
      continue;
    }
    const auto comma = line.find(',');
    double t = 0.0;
    try {
      t = std::stod(line.substr(0, comma));
    } catch (const std::exception&) {
      break;  // a malformed row: keep what came before
    }
    if (t > t_max * (1.0 + 1e-12) + 1e-300) break;
    out += line + "\n";
  }
  return out;
}

ProbeRecorder::ProbeRecorder(const std::vector<Probe>& probes, std::filesystem::path dir, double keep_until,
                             bool fresh)
    : dir_(std::move(dir)) {
  if (probes.empty()) return;
  create_directories_or_throw(dir_);
  for (const Probe& probe : probes) {
    Series s{probe, probe_header(probe) + "\n", 0};
    const auto path = dir_ / (probe.name + ".csv");
    std::error_code ec;
    if (!fresh && std::filesystem::exists(path, ec)) s.text = csv_rows_until(read_file(path), keep_until);
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
    s.text += fmt::format("{}", t);
    for (double v : sample_probe(s.probe, sim)) s.text += fmt::format(",{}", v);
    s.text += "\n";
  }
}

void ProbeRecorder::flush() {
  for (const Series& s : series_) write_file_atomic(dir_ / (s.probe.name + ".csv"), s.text);
}

}  // namespace sluice
