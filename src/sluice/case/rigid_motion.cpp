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

// The elevation the wave maker's target wave has at `s` in front of its face, by first-order theory
// (for order 2 with Stokes' bound second harmonic): a displacement (S/2) sin(omega tau + phi) makes
// the wave a cos(omega tau + phi - k s), a = (H/S)(S/2), ramped as the paddle is.
std::shared_ptr<const ScalarLaw> target_elevation(const MotionLawSpec& m, double g, double s) {
  constexpr double quarter = 0.5 * std::numbers::pi;
  std::vector<SineSumLaw::Term> terms;
  if (m.spectrum == WaveSpectrum::jonswap) {
    const waves::IrregularSea sea = waves::jonswap_sea(m.significant_height, m.peak_period, m.gamma, m.components,
                                                       static_cast<std::uint64_t>(m.seed));
    for (const waves::WaveComponent& c : sea.components) {
      const double omega = 2.0 * std::numbers::pi * c.frequency;
      const double k = waves::wavenumber(omega, m.depth, g);
      terms.push_back({m.gain * c.amplitude, omega, c.phase - k * s + quarter});
    }
    return std::make_shared<SineSumLaw>(std::move(terms), m.start, m.ramp * m.peak_period, 1.0 / sea.df);
  }
  const double omega = 2.0 * std::numbers::pi / m.period;
  const double k = waves::wavenumber(omega, m.depth, g), kh = k * m.depth, a = 0.5 * m.gain * m.height;
  terms.push_back({a, omega, -k * s + quarter});
  if (m.order == 2) {
    const double sh = std::sinh(kh);
    const double a2 = 0.25 * k * a * a * std::cosh(kh) * (2.0 + std::cosh(2.0 * kh)) / (sh * sh * sh);
    terms.push_back({a2, 2.0 * omega, -2.0 * k * s + quarter});
  }
  return std::make_shared<SineSumLaw>(std::move(terms), m.start, m.ramp * m.period, m.period);
}

// An absorbing piston's law: the wave maker's displacement (none for an absorber alone) corrected by
// the surface measured `s` in front of it.
std::shared_ptr<AbsorbingLaw> absorbing_law(const MotionLawSpec& m, double g, double s) {
  const bool alone = m.law == MotionLawType::absorber;
  std::shared_ptr<const ScalarLaw> target = alone ? nullptr : wave_maker_displacement(m, -2.0);
  std::shared_ptr<const ScalarLaw> elevation = alone ? nullptr : target_elevation(m, g, s);
  const double period = m.spectrum == WaveSpectrum::jonswap ? m.peak_period : m.period;
  const double tau = m.absorption_time > 0.0 ? m.absorption_time
                     : alone                 ? 20.0 * std::sqrt(m.depth / g)
                                             : 4.0 * period;
  double limit = m.absorption_limit;
  if (!(limit > 0.0)) limit = alone ? 0.25 * m.depth : target->largest_magnitude(m.start + (m.ramp + 1.0) * period);
  return std::make_shared<AbsorbingLaw>(std::move(target), std::move(elevation), std::sqrt(g / m.depth),
                                        s / std::sqrt(g * m.depth), tau, limit);
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
    case MotionLawType::absorber: return nullptr;  // rigid_motion_of makes it (it needs g and where to measure)
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
RigidMotion<Dim> rigid_motion_of(const Region& wall, double g, double gauge_distance) {
  RigidMotion<Dim> motion;
  const MotionLawSpec& t = wall.translation;
  if (t.law == MotionLawType::absorber || (t.law == MotionLawType::wave && t.absorb)) {
    motion.absorber = absorbing_law(t, g, gauge_distance);
    motion.gauge_distance = gauge_distance;
    motion.translation = motion.absorber;
  } else {
    motion.translation = law_of(t, 1.0, -2.0);
  }
  if (motion.translation) motion.direction = unit_vector<Dim>(wall.translation.direction);
  motion.rotation = law_of(wall.rotation, std::numbers::pi / 180.0, wall.rotation.centre[Dim - 1]);
  if (motion.rotation) {
    for (int d = 0; d < Dim; ++d) motion.centre[d] = wall.rotation.centre[d];
    motion.axis = Dim == 3 ? unit_vector<3>(wall.rotation.axis) : Vec<3>{0.0, 0.0, 1.0};
  }
  return motion;
}

template RigidMotion<2> rigid_motion_of<2>(const Region&, double, double);
template RigidMotion<3> rigid_motion_of<3>(const Region&, double, double);

}  // namespace sluice
