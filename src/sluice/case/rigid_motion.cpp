#include "sluice/case/rigid_motion.hpp"

#include <cmath>
#include <numbers>

namespace sluice {

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
