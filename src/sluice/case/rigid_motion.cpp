#include "sluice/case/rigid_motion.hpp"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "sluice/geometry/wave_theory.hpp"

namespace sluice {

namespace {

// A wave maker: the horizontal displacement of its face at the still-water level. A piston's stroke
// is S = H / (H/S) (Biesel); order 2 adds Madsen's term at twice the frequency, ramped over the same
// time (twice the periods of the second harmonic). A flap (hinge > -1: its hinge's height above the
// floor) has the stroke of its own transfer function, and no second-order term. A JONSWAP spectrum's
// waves are the sum of its components' first-order motions.
std::shared_ptr<const ScalarLaw> wave_maker_displacement(const MotionLawSpec& m, double hinge) {
  const bool flap = hinge > -1.0;
  if (m.spectrum == WaveSpectrum::jonswap) {
    // Irregular waves, first order: each component of elevation amplitude a at frequency f is made by
    // a stroke S = 2a / (H/S) at its own wavenumber, X = (S/2) sin(2 pi f t + phase); the sum ramped
    // over `ramp` peak periods.
    const waves::IrregularSea sea = waves::jonswap_sea(m.significant_height, m.peak_period, m.gamma, m.components,
                                                       static_cast<std::uint64_t>(m.seed));
    std::vector<SineSumLaw::Term> terms;
    for (const waves::WaveComponent& c : sea.components) {
      const double omega = 2.0 * std::numbers::pi * c.frequency;
      const double k = waves::wavenumber(omega, m.depth);
      const double per_stroke =
          flap ? waves::flap_height_per_stroke(k, m.depth, hinge) : waves::piston_height_per_stroke(k * m.depth);
      terms.push_back({m.gain * c.amplitude / per_stroke, omega, c.phase});
    }
    return std::make_shared<SineSumLaw>(std::move(terms), m.start, m.ramp * m.peak_period, 1.0 / sea.df);
  }
  const double omega = 2.0 * std::numbers::pi / m.period;
  const double k = waves::wavenumber(omega, m.depth);
  const double stroke =
      m.height / (flap ? waves::flap_height_per_stroke(k, m.depth, hinge) : waves::piston_height_per_stroke(k * m.depth));
  auto first = std::make_shared<SinusoidalLaw>(m.gain * 0.5 * stroke, m.period, 0.0, m.start, m.ramp);
  if (flap || m.order < 2) return first;
  const double second = waves::madsen_second_order_amplitude(m.height, k, m.depth);
  return std::make_shared<SumLaw>(
      first, std::make_shared<SinusoidalLaw>(m.gain * second, 0.5 * m.period, 0.0, m.start, 2.0 * m.ramp));
}

// One law as a function of time, its values multiplied by `unit` (pi/180 for a rotation's degrees).
// `hinge`: for a rotation, the height of its centre above the floor (a flap's hinge); -2 for a translation.
std::shared_ptr<const ScalarLaw> law_of(const MotionLawSpec& m, double unit, double hinge) {
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
      const auto displacement = wave_maker_displacement(m, hinge);
      if (hinge > -1.0) return std::make_shared<FlapLaw>(displacement, m.depth - hinge);
      return displacement;
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
  motion.translation = law_of(wall.translation, 1.0, -2.0);
  if (motion.translation) motion.direction = unit_vector<Dim>(wall.translation.direction);
  motion.rotation = law_of(wall.rotation, std::numbers::pi / 180.0, wall.rotation.centre[Dim - 1]);
  if (motion.rotation) {
    for (int d = 0; d < Dim; ++d) motion.centre[d] = wall.rotation.centre[d];
    motion.axis = Dim == 3 ? unit_vector<3>(wall.rotation.axis) : Vec<3>{0.0, 0.0, 1.0};
  }
  return motion;
}

template RigidMotion<2> rigid_motion_of<2>(const Region&);
template RigidMotion<3> rigid_motion_of<3>(const Region&);

}  // namespace sluice
