#include "sluice/io/bodies.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <type_traits>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/probes.hpp"

namespace sluice {

std::string body_header(int dimension) {
  if (dimension == 2) return "time,x,y,angle,vx,vy,angular_velocity,fx,fy,moment";
  return "time,x,y,z,angle,vx,vy,vz,angular_velocity,fx,fy,fz,mx,my,mz";
}

BodyRecorder::BodyRecorder(const Simulation& sim, const std::filesystem::path& dir, double interval,
                           double keep_until, bool fresh, bool writes)
    : interval_(interval), writes_(writes) {
  sim.visit([&](const auto& solver) {
    for (const auto& body : solver.bodies().list()) {
      if (!body.moves) continue;
      if (writes_ && series_.empty()) create_directories_or_throw(dir);
      const auto path = dir / (body.name + ".csv");
      Series s{body.id, AppendFile(path, body_header(sim.dimension()) + "\n"), ""};
      std::error_code ec;
      if (writes_ && !fresh && std::filesystem::exists(path, ec)) s.file.resume(csv_rows_until(read_file(path), keep_until));
      series_.push_back(std::move(s));
    }
  });
  if (interval_ > 0.0)
    next_sample_ = static_cast<std::int64_t>(std::floor(keep_until / interval_ + 1e-9)) + (fresh ? 0 : 1);
}

void BodyRecorder::sample(const Simulation& sim) {
  if (series_.empty()) return;
  const double t = sim.time();
  if (interval_ > 0.0) {
    if (t + 1e-12 * interval_ < static_cast<double>(next_sample_) * interval_) return;
    next_sample_ = static_cast<std::int64_t>(std::floor(t / interval_ + 1e-9)) + 1;
  }
  sim.visit([&](const auto& solver) {
    constexpr int Dim = std::remove_cvref_t<decltype(solver.particles())>::dim;
    for (Series& s : series_) {
      const auto load = solver.body_load(s.body);  // collective
      if (!writes_) continue;
      const BodyState<Dim>& b = solver.bodies().motion().state[s.body];
      constexpr double degrees = 180.0 / std::numbers::pi;
      std::string& row = s.rows;
      row += fmt::format("{}", t);
      for (int d = 0; d < Dim; ++d) row += fmt::format(",{}", b.centre[d] + b.displacement[d]);
      row += fmt::format(",{}", degrees * b.angle);
      for (int d = 0; d < Dim; ++d) row += fmt::format(",{}", b.velocity[d]);
      row += fmt::format(",{}", degrees * b.angular_rate);
      for (int d = 0; d < Dim; ++d) row += fmt::format(",{}", load.force[d]);
      if constexpr (Dim == 2) row += fmt::format(",{}", load.moment[2]);
      else
        for (int d = 0; d < 3; ++d) row += fmt::format(",{}", load.moment[d]);
      row += "\n";
    }
  });
}

void BodyRecorder::flush() {
  if (!writes_) return;
  for (Series& s : series_) {
    s.file.append(s.rows);
    s.rows.clear();
  }
}

void BodyRecorder::sync() {
  if (!writes_) return;
  for (Series& s : series_) s.file.sync();
}

}  // namespace sluice
