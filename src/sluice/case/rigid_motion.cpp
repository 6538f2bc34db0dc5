#include "sluice/case/rigid_motion.hpp"

#include <cmath>
#include <numbers>

#include "sluice/geometry/wave_theory.hpp"

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
    case MotionLawType::wave: {
      // A piston: the stroke S = H / (H/S) (Biesel) and, for order 2, Madsen's term at twice the
      // frequency, ramped over the same time (twice the periods of the second harmonic).
      const double omega = 2.0 * std::numbers::pi / m.period;
      const double k = waves::wavenumber(omega, m.depth);
      const double stroke = m.height / waves::piston_height_per_stroke(k * m.depth);
      auto first = std::make_shared<SinusoidalLaw>(unit * m.gain * 0.5 * stroke, m.period, 0.0, m.start, m.ramp);
      if (m.order < 2) return first;
      const double second = waves::madsen_second_order_amplitude(m.height, k, m.depth);
      return std::make_shared<SumLaw>(
          first, std::make_shared<SinusoidalLaw>(unit * m.gain * second, 0.5 * m.period, 0.0, m.start, 2.0 * m.ramp));
    }
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
