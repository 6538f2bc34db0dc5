#include "sluice/case/motions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace fs = std::filesystem;

void load_motion_files(Case& c, const std::string& source) {
  for (std::size_t i = 0; i < c.walls.size(); ++i)
    for (const bool rotation : {false, true}) {
      MotionLawSpec& m = rotation ? c.walls[i].rotation : c.walls[i].translation;
      if (m.law != MotionLawType::file) {
        m.series = nullptr;
        continue;
      }
      const std::string key = fmt::format("wall[{}].{}", i, rotation ? "rotation" : "translation");
      const std::string written = m.file;  // as the case file says it, for messages
      const fs::path given(m.file);
      const fs::path path = given.is_absolute() || c.mesh_directory.empty() ? given : fs::path(c.mesh_directory) / given;
      try {
        m.series = std::make_shared<const MotionSeries>(
            read_motion_csv(path, m.time_column, m.column, m.scale, m.time_offset));
      } catch (const MotionError& e) {
        throw CaseError(fmt::format("{}: {}.file = {}: {}", source, key, quote(written), e.what()));
      }
      std::error_code ec;
      const fs::path absolute = fs::absolute(path, ec).lexically_normal();
      if (!ec) m.file = absolute.string();
      const double last = m.series->times.back();
      if (m.past_end == PastFileEnd::error && c.end_time > last)
        throw CaseError(fmt::format("{}: {}.file = {}: its last time is t = {} s (file time + time_offset), before "
                                    "time.end = {} s; expected a file that covers the run, or {}.past_end = \"hold\" "
                                    "to keep the wall at its last position after it",
                                    source, key, quote(written), last, c.end_time, key));
    }
}

namespace {

// One law as a function of time, its values multiplied by `unit` (pi/180 for a rotation's degrees).
std::shared_ptr<const ScalarLaw> law_of(const MotionLawSpec& m, double unit) {
  switch (m.law) {
    case MotionLawType::none: return nullptr;
    case MotionLawType::linear: return std::make_shared<LinearLaw>(unit * m.speed, m.start, m.end);
    case MotionLawType::polynomial: {
      std::vector<double> c = m.coefficients;
      for (double& k : c) k *= unit;
      return std::make_shared<PolynomialLaw>(std::move(c), m.start, m.end,
                                             m.after == AfterMotion::hold ? AfterInterval::hold : AfterInterval::continue_);
    }
    case MotionLawType::sinusoidal:
      return std::make_shared<SinusoidalLaw>(unit * m.amplitude, m.period, m.phase * std::numbers::pi / 180.0, m.start,
                                             m.ramp);
    case MotionLawType::file: {
      std::vector<double> v = m.series->values;
      for (double& y : v) y *= unit;
      return std::make_shared<TableLaw>(m.series->times, std::move(v));
    }
  }
  return nullptr;
}

template <int Dim>
Vec<Dim> unit_vector(const Vec3& v) {
  Vec<Dim> u{};
  double length = 0.0;
  for (int d = 0; d < Dim; ++d) length += v[d] * v[d];
  length = std::sqrt(length);
  for (int d = 0; d < Dim; ++d) u[d] = v[d] / length;
  return u;
}

}  // namespace

template <int Dim>
RigidMotion<Dim> rigid_motion_of(const Region& wall) {
  RigidMotion<Dim> motion;
  motion.translation = law_of(wall.translation, 1.0);
  if (motion.translation) motion.direction = unit_vector<Dim>(wall.translation.direction);
  motion.rotation = law_of(wall.rotation, std::numbers::pi / 180.0);
  if (motion.rotation) {
    for (int d = 0; d < Dim; ++d) motion.centre[d] = wall.rotation.centre[d];
    motion.axis = Dim == 3 ? unit_vector<3>(wall.rotation.axis) : Vec<3>{0.0, 0.0, 1.0};
  }
  return motion;
}

template RigidMotion<2> rigid_motion_of<2>(const Region&);
template RigidMotion<3> rigid_motion_of<3>(const Region&);

}  // namespace sluice
