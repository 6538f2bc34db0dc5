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

std::string floating_body_header(int dimension) {
  if (dimension == 2)
    return "time,x,y,angle,vx,vy,angular_velocity,fx,fy,moment,spring_fx,spring_fy,spring_moment,damper_fx,damper_fy,"
           "damper_moment,contact_fx,contact_fy,contact_moment";
  return "time,x,y,z,qw,qx,qy,qz,roll,pitch,yaw,vx,vy,vz,wx,wy,wz,fx,fy,fz,mx,my,mz,spring_fx,spring_fy,spring_fz,"
         "spring_mx,spring_my,spring_mz,damper_fx,damper_fy,damper_fz,damper_mx,damper_my,damper_mz,contact_fx,"
         "contact_fy,contact_fz,contact_mx,contact_my,contact_mz";
}

namespace {

// A floating body's row after its time (io/bodies.hpp).
template <int Dim>
std::string floating_row(const FloatingBody& body) {
  constexpr double degrees = 180.0 / std::numbers::pi;
  const FloatingState& s = body.state();
  const auto r = body.restraint();
  std::string row;
  const auto put = [&](const Vec3& v, int n, double scale = 1.0) {
    for (int d = 0; d < n; ++d) row += fmt::format(",{}", scale * v[d]);
  };
  const auto put_moment = [&](const Vec3& m, double scale = 1.0) {
    if constexpr (Dim == 2) row += fmt::format(",{}", scale * m[2]);
    else put(m, 3, scale);
  };
  put(s.centre, Dim);
  if constexpr (Dim == 2) {
    row += fmt::format(",{}", degrees * body.rotation_vector()[2]);
  } else {
    row += fmt::format(",{},{},{},{}", s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z);
    put(body.roll_pitch_yaw(), 3, degrees);
  }
  put(s.velocity, Dim);
  put_moment(s.omega, degrees);
  put(s.water_force, Dim);
  put_moment(s.water_moment);
  put(r.spring_force, Dim);
  put_moment(r.spring_moment);
  put(r.damper_force, Dim);
  put_moment(r.damper_moment);
  put(s.contact_force, Dim);
  put_moment(s.contact_moment);
  return row;
}

}  // namespace

BodyRecorder::BodyRecorder(const Simulation& sim, const std::filesystem::path& dir, double interval,
                           double keep_until, bool fresh, bool writes)
    : interval_(interval), writes_(writes) {
  sim.visit([&](const auto& solver) {
    for (const auto& body : solver.bodies().list()) {
      if (!body.moves) continue;
      if (writes_ && series_.empty()) create_directories_or_throw(dir);
      const auto path = dir / (body.name + ".csv");
      const std::string header = body.floats ? floating_body_header(sim.dimension()) : body_header(sim.dimension());
      Series s{body.id, AppendFile(path, header + "\n"), ""};
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
      const auto& body = solver.bodies().list()[s.body];
      if (body.floats) {
        if (writes_) s.rows += fmt::format("{}", t) + floating_row<Dim>(body.floating) + "\n";
        continue;
      }
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
