// Prescribed motion laws (geometry/motion.hpp): their values, their analytic rates and accelerations
// against finite differences, the published gate lift, the recorded series' spline and its CSV
// reader's errors, and the rigid motion of a body's points.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/load.hpp"
#include "sluice/case/motions.hpp"
#include "sluice/case/rigid_motion.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/geometry/box.hpp"
#include "sluice/geometry/motion.hpp"
#include "sluice/geometry/moving_solid.hpp"
#include "sluice/geometry/polygon.hpp"
#include "sluice/geometry/wave_theory.hpp"

namespace sluice {
namespace {

// The rate and acceleration of `law` at t against central differences of its value and rate.
void expect_derivatives(const ScalarLaw& law, double t, double scale) {
  const double h = 1e-6;
  const LawValue here = law.at(t), before = law.at(t - h), after = law.at(t + h);
  EXPECT_NEAR(here.rate, (after.value - before.value) / (2 * h), 1e-6 * scale) << "rate at t = " << t;
  EXPECT_NEAR(here.acceleration, (after.rate - before.rate) / (2 * h), 1e-5 * scale) << "acceleration at t = " << t;
}

std::string message_of(const std::string& text) {
  try {
    (void)parse_motion_csv(text, "wm.csv", "Time [s]", "WM_Position [m]");
  } catch (const MotionError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a MotionError for:\n" << text;
  return "";
}

void expect_contains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "message: " << text << "\nlacks: " << part;
}

// The gate of Sun, Le Touze & Zhang (2019): y(t) = -285.115 t^3 + 72.305 t^2 + 0.1463 t over
// 0 <= t <= 0.15 s, 0.45 m at 0.1 s and 0.69 m at 0.15 s, then held.
TEST(MotionLaws, ThePublishedGateLift) {
  const PolynomialLaw gate({0.0, 0.1463, 72.305, -285.115}, 0.0, 0.15, AfterInterval::hold);
  EXPECT_NEAR(gate.at(0.1).value, 0.45, 0.005);
  EXPECT_NEAR(gate.at(0.15).value, 0.69, 0.005);
  EXPECT_DOUBLE_EQ(gate.at(0.1).value, -285.115e-3 + 72.305e-2 + 0.1463e-1);
  EXPECT_EQ(gate.at(-1.0).value, 0.0);
  EXPECT_EQ(gate.at(0.3).value, gate.at(0.15).value);
  EXPECT_EQ(gate.at(0.3).rate, 0.0);
  for (double t : {0.01, 0.05, 0.1, 0.14}) expect_derivatives(gate, t, 100.0);
  const PolynomialLaw going_on({0.0, 0.1463, 72.305, -285.115}, 0.0, 0.15, AfterInterval::continue_);
  EXPECT_DOUBLE_EQ(going_on.at(0.2).rate, going_on.at(0.15).rate);
  EXPECT_NEAR(going_on.at(0.2).value, going_on.at(0.15).value + 0.05 * going_on.at(0.15).rate, 1e-12);
  EXPECT_EQ(going_on.at(0.2).acceleration, 0.0);
}

TEST(MotionLaws, LinearMovesAtItsRateBetweenItsTimes) {
  const LinearLaw law(0.2, 1.0, 3.0);
  EXPECT_EQ(law.at(0.5).value, 0.0);
  EXPECT_DOUBLE_EQ(law.at(2.0).value, 0.2);
  EXPECT_EQ(law.at(2.0).rate, 0.2);
  EXPECT_DOUBLE_EQ(law.at(5.0).value, 0.4);
  EXPECT_EQ(law.at(5.0).rate, 0.0);
  EXPECT_THROW(LinearLaw(1.0, 2.0, 2.0), MotionError);
}

TEST(MotionLaws, SinusoidStartsAtRestUnderItsRampAndDerivativesAreExact) {
  const double amplitude = 0.1, period = 1.5;
  const SinusoidalLaw ramped(amplitude, period, 0.3, 0.5, 2.0);
  const LawValue start = ramped.at(0.5 + 1e-12);
  EXPECT_NEAR(start.value, 0.0, 1e-12);
  EXPECT_NEAR(start.rate, 0.0, 1e-9);
  EXPECT_NEAR(start.acceleration, 0.0, 1e-9);
  const SinusoidalLaw plain(amplitude, period, 0.3, 0.5, 0.0);
  for (double t : {0.7, 1.3, 2.9, 3.4}) expect_derivatives(ramped, t, 1.0);
  for (double t : {0.7, 3.6, 5.0}) expect_derivatives(plain, t, 1.0);
  // After the ramp (two periods, to t = 3.5), the ramped law is the plain one.
  for (double t : {3.6, 4.2, 7.7}) {
    EXPECT_NEAR(ramped.at(t).value, plain.at(t).value, 1e-15);
    EXPECT_NEAR(ramped.at(t).acceleration, plain.at(t).acceleration, 1e-12);
  }
  EXPECT_NEAR(plain.at(0.5 + period).value, 0.0, 1e-15);
  EXPECT_GE(plain.largest_magnitude(10.0), plain.at(0.5 + 0.25 * period).value);
}

// When a law stops taking new values: the end of a linear or held polynomial law, the ramp and one
// period of a sinusoid, a series' last time; never for a polynomial that continues at a rate. A body's
// sweep up to then is all it sweeps, whatever the run's end.
TEST(MotionLaws, EachLawSaysWhenItTakesNoNewValue) {
  EXPECT_EQ(LinearLaw(0.2, 1.0, 3.0).settled_after(), 3.0);
  EXPECT_EQ(PolynomialLaw({0.0, 1.0}, 0.5, 2.0, AfterInterval::hold).settled_after(), 2.0);
  EXPECT_TRUE(std::isinf(PolynomialLaw({0.0, 1.0}, 0.5, 2.0, AfterInterval::continue_).settled_after()));
  EXPECT_EQ(PolynomialLaw({0.0, 0.0, 3.0, -1.0}, 0.0, 2.0, AfterInterval::continue_).settled_after(), 2.0);  // at rest at its end
  const SinusoidalLaw ramped(0.1, 1.5, 0.0, 0.5, 2.0);
  EXPECT_DOUBLE_EQ(ramped.settled_after(), 0.5 + 3.0 * 1.5);
  for (double t : {5.2, 6.1, 9.9})  // later values are ones it took in its last period before then
    EXPECT_NEAR(ramped.at(t).value, ramped.at(t - 1.5 * std::ceil((t - 5.0) / 1.5)).value, 1e-12);
  EXPECT_EQ(TableLaw({0.0, 1.0, 4.0}, {0.0, 1.0, 2.0}).settled_after(), 4.0);
  RigidMotion<2> motion;
  EXPECT_EQ(settled_after(motion), 0.0);
  motion.translation = std::make_shared<LinearLaw>(0.2, 1.0, 3.0);
  motion.rotation = std::make_shared<SinusoidalLaw>(0.1, 1.5, 0.0, 0.5, 2.0);
  EXPECT_DOUBLE_EQ(settled_after(motion), 5.0);
}

// The dispersion relation omega^2 = g k tanh(kh) solved to machine precision from deep to shallow
// water, with its deep (k = omega^2/g) and shallow (k = omega/sqrt(g h)) limits.
TEST(WaveTheory, TheWavenumberSolvesTheDispersionRelation) {
  const double g = 9.81;
  for (double period : {0.5, 1.2, 2.0, 5.0, 20.0})
    for (double depth : {0.01, 0.1, 0.4, 1.0, 10.0, 1000.0}) {
      const double omega = 2.0 * std::numbers::pi / period;
      const double k = waves::wavenumber(omega, depth, g);
      // To the few units in the last place that evaluating the relation itself rounds by.
      EXPECT_NEAR(g * k * std::tanh(k * depth) / (omega * omega), 1.0, 1e-15) << period << " s, " << depth << " m";
    }
  const double omega = 2.0 * std::numbers::pi / 1.0;
  EXPECT_NEAR(waves::wavenumber(omega, 1000.0, g), omega * omega / g, 1e-12);
  EXPECT_NEAR(waves::wavenumber(2.0 * std::numbers::pi / 100.0, 0.01, g) * std::sqrt(g * 0.01) / (2.0 * std::numbers::pi / 100.0),
              1.0, 1e-6);
  EXPECT_THROW((void)waves::wavenumber(0.0, 1.0), std::invalid_argument);
  EXPECT_THROW((void)waves::wavenumber(1.0, -1.0), std::invalid_argument);
}

// Biesel's transfer functions: the piston's H/S is kh in shallow water and 2 in deep water; a flap
// hinged at the floor makes half the piston's wave in shallow water and the same in deep water; a
// flap hinged higher makes less, and none as its hinge reaches the surface.
TEST(WaveTheory, TransferFunctionsHaveTheirShallowAndDeepLimits) {
  for (double kh : {1e-3, 1e-2}) {
    EXPECT_NEAR(waves::piston_height_per_stroke(kh) / kh, 1.0, kh);
    EXPECT_NEAR(waves::flap_height_per_stroke(kh, 1.0, 0.0) / (0.5 * kh), 1.0, kh);
  }
  EXPECT_NEAR(waves::piston_height_per_stroke(20.0), 2.0, 1e-12);
  EXPECT_NEAR(waves::flap_height_per_stroke(20.0, 1.0, 0.0), 2.0, 0.1);  // 2 - 2/kh
  const double k = 2.0;  // kh = 2 on h = 1 m
  EXPECT_LT(waves::flap_height_per_stroke(k, 1.0, 0.0), waves::piston_height_per_stroke(2.0));
  EXPECT_LT(waves::flap_height_per_stroke(k, 1.0, 0.1), waves::flap_height_per_stroke(k, 1.0, 0.0));
  EXPECT_NEAR(waves::flap_height_per_stroke(k, 1.0, 1.0 - 1e-7), 0.0, 1e-6);
  // A regular wave's figures: T = 2 s on h = 1 m.
  const waves::RegularWave w = waves::regular_wave(0.1, 2.0, 1.0);
  EXPECT_NEAR(w.wavelength, 2.0 * std::numbers::pi / w.k, 1e-12);
  EXPECT_NEAR(w.celerity, w.wavelength / 2.0, 1e-12);
  EXPECT_GT(w.group_velocity, 0.5 * w.celerity);
  EXPECT_LT(w.group_velocity, w.celerity);
  EXPECT_NEAR(w.miche_steepness, 0.142 * std::tanh(w.kh), 1e-15);
}

// A piston's wave law: (S/2) sin(omega t) with S = H / (H/S), grown over its ramp; second order adds
// Madsen's term at twice the frequency; the rates and accelerations are exact.
TEST(WaveTheory, APistonsLawIsTheStrokeTheTheoryGives) {
  Region paddle;
  paddle.translation.law = MotionLawType::wave;
  paddle.translation.direction = {1.0, 0.0, 0.0};
  paddle.translation.height = 0.08;
  paddle.translation.period = 1.2;
  paddle.translation.depth = 0.4;
  paddle.translation.ramp = 2.0;
  const double omega = 2.0 * std::numbers::pi / 1.2, k = waves::wavenumber(omega, 0.4);
  const double half_stroke = 0.5 * 0.08 / waves::piston_height_per_stroke(k * 0.4);
  const RigidMotion<2> first = rigid_motion_of<2>(paddle);
  for (double t : {2.5, 3.0, 4.45, 7.1})  // after the ramp (2.4 s)
    EXPECT_NEAR(first.translation->at(t).value, half_stroke * std::sin(omega * t), 1e-15);
  for (double t : {0.3, 1.7, 3.3}) expect_derivatives(*first.translation, t, 1.0);
  EXPECT_NEAR(first.translation->at(1e-9).value, 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(first.translation->settled_after(), 3.0 * 1.2);

  paddle.translation.order = 2;
  paddle.translation.gain = 1.1;
  const RigidMotion<2> second = rigid_motion_of<2>(paddle);
  const double x2 = waves::madsen_second_order_amplitude(0.08, k, 0.4);
  // (H^2 / 32 h)(2/n - 3 cosh kh / sinh^3 kh) = +0.000833 m here: with the other sign the piston's
  // second harmonic added to the first-order motion's free wave (docs/waves.md, "Second-order
  // generation": a2 along a flume with gauges every 0.15 m).
  EXPECT_NEAR(x2, 0.000833, 5e-7);
  for (double t : {2.5, 4.45})
    EXPECT_NEAR(second.translation->at(t).value, 1.1 * (half_stroke * std::sin(omega * t) + x2 * std::sin(2.0 * omega * t)),
                1e-15);
  for (double t : {0.3, 1.7, 3.3}) expect_derivatives(*second.translation, t, 1.0);
}

// Active absorption: an absorber alone stays at rest while the surface in front of it is still; a
// wave arriving at the gauge moves it `delay` later (when the wave reaches it) with the wave's water,
// at -sqrt(g/h) eta along its direction; a steady offset of the level is ignored; its displacement is
// continuous between observations and stays within its limit; its state carries it exactly.
TEST(ActiveAbsorption, AnAbsorberMovesWithTheWaterOfAnArrivingWave) {
  const double g = 9.81, h = 0.4, gain = std::sqrt(g / h), delay = 0.05, tau = 4.0, limit = 0.05;
  AbsorbingLaw a(nullptr, nullptr, gain, delay, tau, limit);
  // The first observation is the level it starts from (here 3 mm above the nominal depth): no motion.
  double t = 0.0;
  for (; t < 0.1 - 1e-12; t += 0.001) a.observe(t, 0.003);
  EXPECT_EQ(a.at(t).value, 0.0);
  EXPECT_EQ(a.at(t).rate, 0.0);
  // A crest 1 cm above that level from t = 0.1 s: nothing until it has had time to reach the piston.
  // (the past is kept every delay / 8: the step is smeared over that much earlier)
  for (; t < 0.1 + delay - 0.008; t += 0.001) a.observe(t, 0.013);
  EXPECT_EQ(a.at(t).rate, 0.0) << t;
  for (; t < 0.1 + delay + 0.01; t += 0.001) a.observe(t, 0.013);
  // Then the piston moves back (against its direction into the water) at sqrt(g/h) * 0.01, less the
  // error's mean (a few thousandths of it yet) and the pull back to its target (not yet 1e-4 m).
  EXPECT_NEAR(a.at(t).rate, -gain * 0.01, 0.01 * gain * 0.01);
  EXPECT_LT(a.at(t).rate, 0.0);
  // The displacement is continuous: at the next observation it is the rate times the time since.
  const double x = a.at(t + 0.001).value;
  EXPECT_NEAR(x, a.at(t).value + 0.001 * a.at(t).rate, 1e-15);
  a.observe(t + 0.001, 0.013);
  t += 0.001;
  EXPECT_EQ(a.at(t).value, x);
  EXPECT_EQ(a.at(t).acceleration, 0.0);
  // The state is all there is: a copy set to it continues alike.
  AbsorbingLaw b(nullptr, nullptr, gain, delay, tau, limit);
  b.unpack(a.packed().data());
  for (double s : {0.0, 0.005, 0.01}) {
    EXPECT_EQ(b.at(t + s).value, a.at(t + s).value);
    EXPECT_EQ(b.at(t + s).rate, a.at(t + s).rate);
  }
  for (double s : {0.001, 0.002}) {
    a.observe(t + s, 0.011);
    b.observe(t + s, 0.011);
    EXPECT_EQ(b.packed(), a.packed());
  }
  t += 0.002;
  // A level held 1 cm up for long: the error's mean follows it and the piston returns to its target.
  double furthest = 0.0;
  for (int k = 0; k < 40000; ++k) {
    a.observe(t += 0.001, 0.013);
    furthest = std::max(furthest, std::abs(a.at(t).value));
  }
  EXPECT_NEAR(a.state().mean_error, 0.013, 1e-6);
  EXPECT_GT(furthest, 0.005);
  EXPECT_LT(std::abs(a.at(t).value), 0.01 * furthest);
  // A level far down for long: the piston stops at its limit (at rest there).
  AbsorbingLaw c(nullptr, nullptr, gain, delay, 100.0, limit);
  c.observe(0.0, 0.0);
  for (int k = 1; k <= 100; ++k) c.observe(0.01 * k, -0.05);
  EXPECT_EQ(c.at(1.5).value, limit);
  EXPECT_EQ(c.at(1.5).rate, 0.0);
  EXPECT_DOUBLE_EQ(c.largest_magnitude(10.0), limit);
  EXPECT_THROW(AbsorbingLaw(nullptr, nullptr, 0.0, delay, tau, limit), MotionError);
  EXPECT_THROW(AbsorbingLaw(nullptr, nullptr, gain, delay, tau, 0.0), MotionError);
}

// An absorbing wave maker: its law is the wave maker's while the surface in front of it is the
// target's (the first-order wave (H/2) cos(omega t - k s) there, for the displacement (S/2) sin(omega
// t)), and its target elevation is that wave's.
TEST(ActiveAbsorption, AnAbsorbingPistonFollowsItsTargetWhileTheSurfaceIsTheTargets) {
  Region paddle;
  paddle.translation.law = MotionLawType::wave;
  paddle.translation.direction = {1.0, 0.0, 0.0};
  paddle.translation.height = 0.08;
  paddle.translation.period = 1.2;
  paddle.translation.depth = 0.4;
  paddle.translation.ramp = 2.0;
  const RigidMotion<2> plain = rigid_motion_of<2>(paddle);
  paddle.translation.absorb = true;
  const double s = 0.1;
  const RigidMotion<2> absorbing = rigid_motion_of<2>(paddle, 9.81, s);
  ASSERT_TRUE(absorbing.absorber);
  EXPECT_EQ(absorbing.translation.get(), absorbing.absorber.get());
  EXPECT_EQ(absorbing.gauge_distance, s);
  const double omega = 2.0 * std::numbers::pi / 1.2, k = waves::wavenumber(omega, 0.4, 9.81);
  AbsorbingLaw& law = *absorbing.absorber;
  for (double t : {2.5, 3.1}) EXPECT_NEAR(law.target_elevation(t), 0.04 * std::cos(omega * t - k * s), 1e-15);
  // Defaults: drawn back over 4 periods, within the half-stroke.
  EXPECT_NEAR(law.limit(), 0.5 * 0.08 / waves::piston_height_per_stroke(k * 0.4), 1e-12);
  for (double t = 0.0; t < 6.0; t += 0.001) {
    law.observe(t, law.target_elevation(t));
    EXPECT_EQ(law.at(t).value, plain.translation->at(t).value) << t;
    EXPECT_EQ(law.at(t).rate, plain.translation->at(t).rate) << t;
  }
}

// A flap's wave law: the angle -atan(X / (h - hinge)) of the displacement X = (S/2) sin(omega t) that
// the flap's transfer function asks of its face at the still-water level; its rates and accelerations
// are exact, and its top swings to +x first (in 2D, a negative angle about z).
TEST(WaveTheory, AFlapsLawIsTheAngleOfItsStrokeAtTheSurface) {
  Region flap;
  flap.rotation.law = MotionLawType::wave;
  flap.rotation.centre = {0.08, 0.1, 0.0};
  flap.rotation.height = 0.08;
  flap.rotation.period = 1.2;
  flap.rotation.depth = 0.4;
  flap.rotation.ramp = 2.0;
  const double omega = 2.0 * std::numbers::pi / 1.2, k = waves::wavenumber(omega, 0.4);
  const double half_stroke = 0.5 * 0.08 / waves::flap_height_per_stroke(k, 0.4, 0.1);
  const RigidMotion<2> motion = rigid_motion_of<2>(flap);
  for (double t : {2.5, 3.0, 4.45, 7.1})
    EXPECT_NEAR(motion.rotation->at(t).value, -std::atan(half_stroke * std::sin(omega * t) / 0.3), 1e-15);
  for (double t : {0.3, 1.7, 2.9, 3.3}) expect_derivatives(*motion.rotation, t, 1.0);
  EXPECT_LT(motion.rotation->at(2.4 + 0.3).value, 0.0);  // a quarter period after the ramp: the top is furthest out
  EXPECT_DOUBLE_EQ(motion.rotation->settled_after(), 3.0 * 1.2);
  EXPECT_NEAR(motion.rotation->largest_magnitude(10.0), std::atan(half_stroke / 0.3), 1e-15);
}

// A JONSWAP sea discretised: its m0 gives 4 sqrt(m0) = Hs; the continuous shape and the components
// peak at fp; amplitudes follow a = sqrt(2 S(f) df) in equal bins of fp/M from fp/2 to about 3 fp; the
// shape's integral is the Pierson-Moskowitz one for gamma = 1 and DNV's normalisation above it; the
// phases are the raw mt19937_64 draws of the seed, the same on every platform.
TEST(WaveTheory, AJonswapSeaCarriesItsSignificantHeightAndPeaksAtTheSpectralPeak) {
  const double hs = 0.06, tp = 1.2, fp = 1.0 / tp;
  for (const double gamma : {1.0, 3.3, 7.0}) {
    const waves::IrregularSea sea = waves::jonswap_sea(hs, tp, gamma, 200, 1);
    ASSERT_EQ(sea.components.size(), 200u);
    EXPECT_NEAR(4.0 * std::sqrt(waves::zeroth_moment(sea)), hs, 1e-6 * hs) << "gamma " << gamma;
    EXPECT_DOUBLE_EQ(sea.df, fp / 80.0);
    EXPECT_DOUBLE_EQ(sea.components.front().frequency, 0.5 * fp);
    EXPECT_DOUBLE_EQ(sea.components.back().frequency, 239.0 * fp / 80.0);
    std::size_t largest = 0;
    for (std::size_t n = 0; n < sea.components.size(); ++n) {
      if (sea.components[n].amplitude > sea.components[largest].amplitude) largest = n;
      if (n > 0) {
        EXPECT_NEAR(sea.components[n].frequency - sea.components[n - 1].frequency, sea.df, 1e-12);
      }
      EXPECT_GE(sea.components[n].phase, 0.0);
      EXPECT_LT(sea.components[n].phase, 2.0 * std::numbers::pi);
    }
    EXPECT_DOUBLE_EQ(sea.components[largest].frequency, fp) << "gamma " << gamma;
    // a^2 is proportional to S(f): the ratio of two components' is the shape's.
    const auto& c = sea.components;
    EXPECT_NEAR(c[10].amplitude * c[10].amplitude / (c[120].amplitude * c[120].amplitude),
                waves::jonswap_shape(c[10].frequency, fp, gamma) / waves::jonswap_shape(c[120].frequency, fp, gamma), 1e-9);
    // The continuous shape's maximum, sampled every 1e-5 fp.
    double best_f = 0.0, best = 0.0;
    for (int i = 0; i <= 150000; ++i) {
      const double f = fp * (0.5 + 1e-5 * i);
      const double s = waves::jonswap_shape(f, fp, gamma);
      if (s > best) {
        best = s;
        best_f = f;
      }
    }
    EXPECT_NEAR(best_f / fp, 1.0, 2e-5) << "gamma " << gamma;
    // The continuous shape's integral: for gamma = 1 (Pierson-Moskowitz) exactly Tp^4 / 5; the peak
    // enhancement raises it by 1 / (1 - 0.287 ln gamma), the normalisation DNV-RP-C205 (3.5.5.4) gives,
    // to its 2 % for gamma up to 7.
    double integral = 0.0;
    const double step = 1e-4 * fp;
    for (double f = 0.2 * fp; f < 100.0 * fp; f += step) integral += waves::jonswap_shape(f + 0.5 * step, fp, gamma) * step;
    EXPECT_NEAR(integral / (std::pow(tp, 4.0) / 5.0) * (1.0 - 0.287 * std::log(gamma)), 1.0, gamma == 1.0 ? 1e-5 : 0.02)
        << "gamma " << gamma;
    // The band holds most of the spectrum: what lies above 3 fp is a tail of f^-5.
    EXPECT_GT(sea.band_share, 0.98);
    EXPECT_LT(sea.band_share, 1.0);
  }
  // Phases: 2 pi (u >> 11) 2^-53 of the seed's mt19937_64 draws, in frequency order.
  const waves::IrregularSea one = waves::jonswap_sea(hs, tp, 3.3, 200, 1);
  EXPECT_DOUBLE_EQ(one.components[0].phase, 2.0 * std::numbers::pi * static_cast<double>(2469588189546311528ULL >> 11) * 0x1p-53);
  EXPECT_DOUBLE_EQ(one.components[1].phase, 0.85707068669200193);
  EXPECT_DOUBLE_EQ(one.components[2].phase, 2.8350668542164517);
  const waves::IrregularSea again = waves::jonswap_sea(hs, tp, 3.3, 200, 1), other = waves::jonswap_sea(hs, tp, 3.3, 200, 2);
  int same = 0;
  for (std::size_t n = 0; n < 200; ++n) {
    EXPECT_EQ(again.components[n].phase, one.components[n].phase);
    EXPECT_EQ(other.components[n].amplitude, one.components[n].amplitude);
    same += other.components[n].phase == one.components[n].phase;
  }
  EXPECT_EQ(same, 0);
  // One component is the peak's, carrying all of m0: a = Hs / (2 sqrt 2); two are fp and 2 fp.
  const waves::IrregularSea single = waves::jonswap_sea(hs, tp, 3.3, 1, 1);
  ASSERT_EQ(single.components.size(), 1u);
  EXPECT_DOUBLE_EQ(single.components[0].frequency, fp);
  EXPECT_NEAR(single.components[0].amplitude, hs / (2.0 * std::sqrt(2.0)), 1e-15);
  const waves::IrregularSea pair = waves::jonswap_sea(hs, tp, 3.3, 2, 1);
  EXPECT_DOUBLE_EQ(pair.components[0].frequency, fp);
  EXPECT_DOUBLE_EQ(pair.components[1].frequency, 2.0 * fp);
  EXPECT_THROW((void)waves::jonswap_sea(0.0, tp, 3.3, 10, 1), std::invalid_argument);
  EXPECT_THROW((void)waves::jonswap_sea(hs, tp, 0.5, 10, 1), std::invalid_argument);
  EXPECT_THROW((void)waves::jonswap_sea(hs, tp, 3.3, 0, 1), std::invalid_argument);
}

// A JONSWAP piston: the sum of each component's first-order stroke a / (H/S) at its own wavenumber,
// times gain, ramped over `ramp` peak periods; exact rates and accelerations; it repeats every 1/df
// after the ramp; a seed gives the same motion, another seed another. One component is the regular
// maker's wave of the same energy at Tp. A flap turns by -atan(X / (h - hinge)) of its own strokes.
// The regular law is still SinusoidalLaw to the bit.
TEST(WaveTheory, AJonswapWaveMakerIsTheSumOfItsComponentsStrokes) {
  Region paddle;
  MotionLawSpec& m = paddle.translation;
  m.law = MotionLawType::wave;
  m.spectrum = WaveSpectrum::jonswap;
  m.direction = {1.0, 0.0, 0.0};
  m.significant_height = 0.06;
  m.peak_period = 1.2;
  m.depth = 0.4;
  m.ramp = 2.0;
  m.components = 50;
  m.seed = 7;
  const waves::IrregularSea sea = waves::jonswap_sea(0.06, 1.2, 3.3, 50, 7);
  const auto expected = [&](double t, bool flap) {
    double x = 0.0;
    for (const auto& c : sea.components) {
      const double omega = 2.0 * std::numbers::pi * c.frequency, k = waves::wavenumber(omega, 0.4);
      const double per_stroke = flap ? waves::flap_height_per_stroke(k, 0.4, 0.1) : waves::piston_height_per_stroke(k * 0.4);
      x += c.amplitude / per_stroke * std::sin(omega * t + c.phase);
    }
    return x;
  };
  const RigidMotion<2> motion = rigid_motion_of<2>(paddle);
  const ScalarLaw& law = *motion.translation;
  double largest = 0.0;
  for (double t = 2.4; t < 30.0; t += 0.05) {
    EXPECT_NEAR(law.at(t).value, expected(t, false), 1e-14) << "t = " << t;
    largest = std::max(largest, std::abs(law.at(t).value));
  }
  EXPECT_GT(largest, 0.01);  // a stroke of centimetres: the sum is not empty
  for (double t : {0.3, 1.1, 2.0, 2.39, 2.41, 5.3, 17.7}) expect_derivatives(law, t, 1.0);
  EXPECT_EQ(law.at(0.0).value, 0.0);
  EXPECT_NEAR(law.at(1e-9).value, 0.0, 1e-15);
  EXPECT_NEAR(law.at(1e-9).rate, 0.0, 1e-9);
  // M = 20 bins per fp: the waves repeat every 20 Tp = 24 s.
  EXPECT_NEAR(law.settled_after(), 2.4 + 24.0, 1e-9);
  for (double t : {3.0, 7.7, 11.2}) EXPECT_NEAR(law.at(t + 24.0).value, law.at(t).value, 1e-12);

  // The same seed: the same motion, to the bit; another seed: another motion; gain scales it.
  const RigidMotion<2> again = rigid_motion_of<2>(paddle);
  m.seed = 8;
  const RigidMotion<2> reseeded = rigid_motion_of<2>(paddle);
  m.seed = 7;
  m.gain = 1.5;
  const RigidMotion<2> gained = rigid_motion_of<2>(paddle);
  m.gain = 1.0;
  double difference = 0.0;
  for (double t = 0.0; t < 20.0; t += 0.1) {
    EXPECT_EQ(again.translation->at(t).value, law.at(t).value);
    EXPECT_EQ(again.translation->at(t).acceleration, law.at(t).acceleration);
    EXPECT_NEAR(gained.translation->at(t).value, 1.5 * law.at(t).value, 1e-15);
    difference = std::max(difference, std::abs(reseeded.translation->at(t).value - law.at(t).value));
  }
  EXPECT_GT(difference, 0.005);

  // One component: a sinusoid at Tp whose amplitude is the regular maker's for H = Hs / sqrt 2.
  m.components = 1;
  const RigidMotion<2> single = rigid_motion_of<2>(paddle);
  const double omega = 2.0 * std::numbers::pi / 1.2, k = waves::wavenumber(omega, 0.4);
  const double half_stroke = 0.5 * (0.06 / std::sqrt(2.0)) / waves::piston_height_per_stroke(k * 0.4);
  for (double t : {2.5, 3.1, 9.75}) {
    const LawValue x = single.translation->at(t);
    EXPECT_NEAR(std::hypot(x.value, x.rate / omega), half_stroke, 1e-15);
    EXPECT_NEAR(x.acceleration, -omega * omega * x.value, 1e-13);
  }
  EXPECT_NEAR(single.translation->settled_after(), 2.4 + 1.2, 1e-12);
  m.components = 50;

  // A flap hinged 0.1 m above the floor.
  Region flap;
  flap.rotation = m;
  flap.rotation.direction = {};
  flap.rotation.centre = {0.08, 0.1, 0.0};
  const RigidMotion<2> turning = rigid_motion_of<2>(flap);
  for (double t : {2.5, 4.45, 13.1})
    EXPECT_NEAR(turning.rotation->at(t).value, -std::atan(expected(t, true) / 0.3), 1e-14) << "t = " << t;
  for (double t : {0.7, 2.2, 6.1}) expect_derivatives(*turning.rotation, t, 1.0);

  // The regular law is SinusoidalLaw as it was, bit for bit.
  Region regular;
  regular.translation.law = MotionLawType::wave;
  regular.translation.direction = {1.0, 0.0, 0.0};
  regular.translation.height = 0.08;
  regular.translation.period = 1.2;
  regular.translation.depth = 0.4;
  regular.translation.ramp = 2.0;
  const double regular_stroke = 0.08 / waves::piston_height_per_stroke(waves::wavenumber(omega, 0.4) * 0.4);
  const SinusoidalLaw sine(1.0 * 0.5 * regular_stroke, 1.2, 0.0, 0.0, 2.0);
  const RigidMotion<2> regular_motion = rigid_motion_of<2>(regular);
  for (double t = 0.0; t < 10.0; t += 0.37) {
    const LawValue a = regular_motion.translation->at(t), b = sine.at(t);
    EXPECT_EQ(a.value, b.value);
    EXPECT_EQ(a.rate, b.rate);
    EXPECT_EQ(a.acceleration, b.acceleration);
  }
}

// A recorded series: the natural cubic spline passes through every sample, its rate and acceleration
// are continuous across them, and on a dense sampling of a sine it gives the sine's acceleration.
TEST(MotionLaws, TableSplineIsTwiceDifferentiable) {
  std::vector<double> t, y;
  const double omega = 2.0 * std::numbers::pi / 2.0;
  for (int k = 0; k <= 400; ++k) {
    t.push_back(0.01 * k);
    y.push_back(0.05 * std::sin(omega * 0.01 * k));
  }
  const TableLaw law(t, y);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(law.at(t[k]).value, y[k], 1e-15) << k;
  for (double at : {1.0, 2.5}) {  // sample times: both sides agree
    const LawValue left = law.at(at - 1e-10), right = law.at(at + 1e-10);
    EXPECT_NEAR(left.rate, right.rate, 1e-7);
    EXPECT_NEAR(left.acceleration, right.acceleration, 1e-6);
  }
  for (double at : {0.505, 1.333, 3.07}) {
    expect_derivatives(law, at, 1.0);
    EXPECT_NEAR(law.at(at).acceleration, -0.05 * omega * omega * std::sin(omega * at), 0.002 * 0.05 * omega * omega);
  }
  EXPECT_EQ(law.at(-1.0).value, y.front());
  EXPECT_EQ(law.at(9.0).value, y.back());
  EXPECT_EQ(law.at(9.0).rate, 0.0);
  EXPECT_THROW(TableLaw({0.0, 1.0, 1.0}, {0.0, 1.0, 2.0}), MotionError);
}

TEST(MotionCsv, ColumnsByNameWithScaleAndOffset) {
  const std::string text =
      "# source: a wave maker's record\n"
      "Time [s],WM_Position [m],WP_1 [m]\n"
      "14.98,0.002,9\n"
      "14.99,0.004,9\n"
      "\n"
      "15.00,-0.001,9\r\n";
  const MotionSeries s = parse_motion_csv(text, "wm.csv", "Time [s]", "WM_Position [m]", 10.0, -14.98);
  ASSERT_EQ(s.times.size(), 3u);
  EXPECT_NEAR(s.times[0], 0.0, 1e-12);
  EXPECT_NEAR(s.times[2], 0.02, 1e-12);
  EXPECT_DOUBLE_EQ(s.values[1], 0.04);
  EXPECT_DOUBLE_EQ(s.values[2], -0.01);
}

TEST(MotionCsv, BadFilesAreNamedWithWhatWasExpected) {
  expect_contains(message_of(""), "wm.csv: empty; expected a header line");
  expect_contains(message_of("Time [s],Paddle\n0,1\n"),
                  "wm.csv: no column \"WM_Position [m]\" in its header (line 1); its columns are \"Time [s]\", \"Paddle\"");
  expect_contains(message_of("Time [s],WM_Position [m]\n0,0\n0.1,nan\n"),
                  "wm.csv:3: column \"WM_Position [m]\": 'nan' is not a finite number");
  expect_contains(message_of("Time [s],WM_Position [m]\n0,0\n0.1,1x\n"), "'1x' is not a finite number");
  expect_contains(message_of("Time [s],WM_Position [m]\n0,0\n0.2,1\n0.1,2\n"),
                  "wm.csv:4: the time 0.1 does not increase (the row before has 0.2)");
  expect_contains(message_of("Time [s],WM_Position [m]\n0,0\n"), "1 row(s) of data; expected at least two");
  expect_contains(message_of("Time [s],WM_Position [m]\n0\n"), "wm.csv:2: the row has 1 columns, without \"WM_Position [m]\"");
  const auto missing = std::filesystem::temp_directory_path() / "sluice_no_such_motion.csv";
  try {
    (void)read_motion_csv(missing, "t", "x");
    ADD_FAILURE() << "no error for a missing file";
  } catch (const MotionError& e) {
    expect_contains(e.what(), "sluice_no_such_motion.csv: no such file");
  }
  try {
    (void)read_motion_csv(std::filesystem::temp_directory_path(), "t", "x");
    ADD_FAILURE() << "no error for a directory";
  } catch (const MotionError& e) {
    expect_contains(e.what(), "is a directory");
  }
}

// A point of a body turning about a centre that itself moves: on the circle about the moving centre,
// with the velocity and acceleration of rigid motion, which central differences of its positions confirm.
template <int Dim>
void check_rigid_motion(const RigidMotion<Dim>& motion, const Vec<Dim>& start) {
  const double h = 1e-6;
  for (double t : {0.3, 1.1, 2.4}) {
    const PointMotion<Dim> now = point_motion<Dim>(body_state(motion, t), start);
    const PointMotion<Dim> before = point_motion<Dim>(body_state(motion, t - h), start);
    const PointMotion<Dim> after = point_motion<Dim>(body_state(motion, t + h), start);
    for (int d = 0; d < Dim; ++d) {
      EXPECT_NEAR(now.velocity[d], (after.position[d] - before.position[d]) / (2 * h), 1e-6) << "t " << t << " d " << d;
      EXPECT_NEAR(now.acceleration[d], (after.velocity[d] - before.velocity[d]) / (2 * h), 1e-5) << "t " << t << " d " << d;
    }
    // The radius about the centre is kept, and to_start takes the point back.
    const BodyState<Dim> s = body_state(motion, t);
    EXPECT_NEAR(norm(now.position - s.centre - s.displacement), norm(start - s.centre), 1e-12);
    const Vec<Dim> back = to_start<Dim>(s, now.position);
    for (int d = 0; d < Dim; ++d) EXPECT_NEAR(back[d], start[d], 1e-12);
  }
}

TEST(RigidMotion, RotationAboutATranslatingCentre2D) {
  RigidMotion<2> motion;
  motion.translation = std::make_shared<SinusoidalLaw>(0.2, 2.0, 0.0, 0.0, 1.0);
  motion.direction = {1.0, 0.0};
  motion.rotation = std::make_shared<SinusoidalLaw>(0.1, 1.7, 0.0, 0.0, 0.5);
  motion.centre = {1.0, 0.5};
  check_rigid_motion<2>(motion, {1.8, 0.1});
  // A quarter turn about the centre: (1, 0) from it goes to (0, 1).
  RigidMotion<2> quarter;
  quarter.rotation = std::make_shared<LinearLaw>(std::numbers::pi / 2, 0.0, 1.0);
  quarter.centre = {1.0, 1.0};
  const PointMotion<2> m = point_motion<2>(body_state(quarter, 1.0), Vec<2>{2.0, 1.0});
  EXPECT_NEAR(m.position[0], 1.0, 1e-15);
  EXPECT_NEAR(m.position[1], 2.0, 1e-15);
  const Vec<2> n = rotate_to_now<2>(body_state(quarter, 1.0), Vec<2>{1.0, 0.0});
  EXPECT_NEAR(n[0], 0.0, 1e-15);
  EXPECT_NEAR(n[1], 1.0, 1e-15);
}

TEST(RigidMotion, RollAboutATiltedAxis3D) {
  RigidMotion<3> motion;
  motion.translation = std::make_shared<PolynomialLaw>(std::vector<double>{0.0, 0.1, 0.3}, 0.0, 3.0, AfterInterval::hold);
  motion.direction = {0.0, 0.6, 0.8};
  motion.rotation = std::make_shared<SinusoidalLaw>(0.2, 1.3, 0.4, 0.1, 1.0);
  const double s = 1.0 / std::sqrt(3.0);
  motion.axis = {s, s, s};
  motion.centre = {0.5, 0.2, 0.1};
  check_rigid_motion<3>(motion, {0.9, -0.3, 0.6});
}

// The moving solid and the shape built where it now is give the same inside test, distance, closest
// point and normal at each of `points`.
void expect_same_answers(const Solid<2>& moving, const Solid<2>& there, const std::vector<Vec<2>>& points,
                         double tolerance) {
  for (const Vec<2>& x : points) {
    EXPECT_EQ(moving.contains(x), there.contains(x)) << x[0] << " " << x[1];
    EXPECT_NEAR(moving.signed_distance(x), there.signed_distance(x), tolerance);
    const SurfacePoint<2> a = moving.closest_surface_point(x), b = there.closest_surface_point(x);
    for (int d = 0; d < 2; ++d) {
      EXPECT_NEAR(a.point[d], b.point[d], tolerance);
      EXPECT_NEAR(a.normal[d], b.normal[d], tolerance);
    }
  }
}

// A moving solid answers every query at its current pose: a box lifted like a gate, and a polygon
// turned about a point, against the same shape built where the motion has taken it.
TEST(MovingSolid, AGateLiftedIsTheBoxWhereItNowIs) {
  auto gate = std::make_shared<Box<2>>(Vec<2>{0.2, 0.0}, Vec<2>{0.22, 0.6});
  MovingSolid<2> moving(gate);
  EXPECT_TRUE(moving.is_box());
  RigidMotion<2> lift;
  lift.translation = std::make_shared<PolynomialLaw>(std::vector<double>{0.0, 0.1463, 72.305, -285.115}, 0.0, 0.15,
                                                     AfterInterval::hold);
  lift.direction = {0.0, 1.0};
  moving.set_state(body_state(lift, 0.1));
  const double y = lift.translation->at(0.1).value;
  const Box<2> there({0.2, y}, {0.22, 0.6 + y});
  EXPECT_TRUE(moving.is_box());
  EXPECT_NEAR(moving.lower()[1], y, 1e-15);
  EXPECT_NEAR(moving.upper()[1], 0.6 + y, 1e-15);
  expect_same_answers(moving, there, {{0.21, 0.1}, {0.21, 0.3}, {0.25, 0.5}, {0.1, 1.2}, {0.21, 1.05}}, 1e-14);
  // Its wall particles are the lifted box's.
  std::vector<Vec<2>> mine, theirs;
  moving.fill_surface_layers(0.01, 2, [&](const Vec<2>& q) { mine.push_back(q); });
  there.fill_surface_layers(0.01, 2, [&](const Vec<2>& q) { theirs.push_back(q); });
  ASSERT_EQ(mine.size(), theirs.size());
  for (std::size_t k = 0; k < mine.size(); ++k)
    for (int d = 0; d < 2; ++d) EXPECT_NEAR(mine[k][d], theirs[k][d], 1e-14);
}

TEST(MovingSolid, ATurnedPolygonIsThePolygonTurned) {
  const std::vector<Vec2> triangle{{1.0, 0.0}, {2.0, 0.0}, {2.0, 0.5}};
  MovingSolid<2> moving(std::make_shared<Polygon>(triangle));
  RigidMotion<2> roll;
  roll.rotation = std::make_shared<LinearLaw>(0.3, 0.0, 10.0);
  roll.centre = {1.0, 1.0};
  const BodyState<2> state = body_state(roll, 2.0);  // 0.6 rad
  moving.set_state(state);
  EXPECT_FALSE(moving.is_box());
  std::vector<Vec2> turned;
  for (const Vec2& v : triangle) turned.push_back(point_motion<2>(state, v).position);
  const Polygon there(turned);
  expect_same_answers(moving, there, {{1.5, 0.5}, {1.9, 0.9}, {1.2, 0.2}, {2.5, 1.5}, {0.5, -0.5}}, 1e-12);
  for (int d = 0; d < 2; ++d) {
    EXPECT_LE(moving.lower()[d], there.lower()[d] + 1e-12);
    EXPECT_GE(moving.upper()[d], there.upper()[d] - 1e-12);
  }
}

TEST(MovingSolid, ABoxRolledIn3DAnswersAtItsPose) {
  auto box = std::make_shared<Box<3>>(Vec<3>{0.0, 0.0, 0.0}, Vec<3>{1.0, 0.5, 0.2});
  MovingSolid<3> moving(box);
  RigidMotion<3> roll;
  roll.rotation = std::make_shared<LinearLaw>(std::numbers::pi / 2, 0.0, 1.0);
  roll.axis = {1.0, 0.0, 0.0};
  roll.centre = {0.0, 0.0, 0.0};
  moving.set_state(body_state(roll, 1.0));  // a quarter turn about x: y -> z, z -> -y
  const Box<3> there({0.0, -0.2, 0.0}, {1.0, 0.0, 0.5});
  for (const Vec<3> x : {Vec<3>{0.5, -0.1, 0.25}, Vec<3>{0.5, 0.1, 0.25}, Vec<3>{0.5, -0.1, 0.6}, Vec<3>{1.2, -0.3, -0.1}}) {
    EXPECT_EQ(moving.contains(x), there.contains(x)) << x[0] << " " << x[1] << " " << x[2];
    EXPECT_NEAR(moving.signed_distance(x), there.signed_distance(x), 1e-12);
  }
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(moving.lower()[d], there.lower()[d], 1e-12);
    EXPECT_NEAR(moving.upper()[d], there.upper()[d], 1e-12);
  }
}

}  // namespace
}  // namespace sluice

namespace sluice {
namespace {

// From a case file to a wall's motion: the laws as written (a rotation in degrees), a motion file read
// beside the case file by column name, and a file that ends before the run refused.
TEST(WallMotionFromCase, TheLawsAsTheCaseWritesThem) {
  const auto dir = std::filesystem::temp_directory_path() / "sluice_test_wall_motion";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  {
    std::ofstream csv(dir / "paddle.csv");
    csv << "# a paddle's record\nTime [s],Pos [mm]\n0,0\n0.5,10\n1.0,0\n1.5,-10\n2.0,0\n";
  }
  const std::string walls = R"([[water]]
min = [0.0, 0.0]
max = [1.0, 1.0]
[[wall]]
name = "gate"
min = [1.2, 0.0]
max = [1.22, 0.6]
[wall.translation]
law = "polynomial"
direction = [0.0, 1.0]
coefficients = [0.0, 0.1463, 72.305, -285.115]
end = 0.15
[[wall]]
name = "paddle"
min = [5.0, 0.0]
max = [5.1, 1.0]
[wall.translation]
law = "file"
direction = [-1.0, 0.0]
file = "paddle.csv"
time_column = "Time [s]"
column = "Pos [mm]"
scale = 0.001
[wall.rotation]
law = "sinusoidal"
centre = [5.05, 0.0]
amplitude = 10.0
period = 2.0
)";
  {
    std::ofstream toml(dir / "case.toml");
    toml << "[time]\nend = 1.5\n" << walls;
  }
  const Case c = load_case_file(dir / "case.toml");
  const BodyState<2> gate = body_state(rigid_motion_of<2>(c.walls[0]), 0.1);
  EXPECT_NEAR(gate.displacement[1], 0.452565, 1e-12);
  EXPECT_EQ(gate.displacement[0], 0.0);
  const RigidMotion<2> paddle = rigid_motion_of<2>(c.walls[1]);
  const BodyState<2> at = body_state(paddle, 0.5);
  EXPECT_NEAR(at.displacement[0], -0.01, 1e-15);  // 10 mm along -x
  EXPECT_NEAR(at.angle, 10.0 * std::numbers::pi / 180.0 * std::sin(std::numbers::pi / 2), 1e-12);
  EXPECT_EQ(c.walls[1].translation.file, (dir / "paddle.csv").string());
  // The same case to t = 3 s runs past the file's 2 s.
  {
    std::ofstream toml(dir / "case.toml");
    toml << "[time]\nend = 3.0\n" << walls;
  }
  try {
    (void)load_case_file(dir / "case.toml");
    ADD_FAILURE() << "a motion file shorter than the run was accepted";
  } catch (const CaseError& e) {
    expect_contains(e.what(), "wall[1].translation.file = \"paddle.csv\": its last time is t = 2 s");
    expect_contains(e.what(), "before time.end = 3 s");
    expect_contains(e.what(), "wall[1].translation.past_end = \"hold\"");
  }
  std::filesystem::remove(dir / "paddle.csv");
  try {
    (void)load_case_file(dir / "case.toml");
    ADD_FAILURE() << "a missing motion file was accepted";
  } catch (const CaseError& e) {
    expect_contains(e.what(), "wall[1].translation.file = \"paddle.csv\":");
    expect_contains(e.what(), "paddle.csv: no such file");
  }
  std::filesystem::remove_all(dir);
}

// A record built into the binary (data/validation/) drives a wall by its name alone: the built-in
// NTNU flume's flap follows the laboratory's paddle from t = 1 s, and a case file naming the record
// finds it when there is no file of that name beside it.
TEST(WallMotionFromCase, ABuiltInRecordIsFoundByName) {
  const auto ntnu = load_builtin_case("ntnu_flume");
  ASSERT_TRUE(ntnu);
  const MotionLawSpec& flap = ntnu->walls.at(1).rotation;
  ASSERT_EQ(flap.law, MotionLawType::file);
  ASSERT_TRUE(flap.series);
  EXPECT_EQ(flap.file, "ntnu_flume2025_1062.csv");
  // 100 Hz from 4 s before the paddle moves to 45 s after: 4,900 samples.
  EXPECT_EQ(flap.series->times.size(), 4900u);
  EXPECT_NEAR(flap.series->times.front(), 14.98 - 17.98, 1e-12);
  // Still before t = 1 s, then up to 0.014 m / 0.9 m = 0.89 degrees.
  double before = 0.0, after = 0.0;
  for (std::size_t j = 0; j < flap.series->times.size(); ++j)
    (flap.series->times[j] < 0.9 ? before : after) =
        std::max(flap.series->times[j] < 0.9 ? before : after, std::abs(flap.series->values[j]));
  EXPECT_LT(before, 0.01);
  EXPECT_NEAR(after, 0.0140 * 63.662, 0.01);

  const auto dir = std::filesystem::temp_directory_path() / "sluice_test_builtin_record";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "case.toml") << R"([tank]
width = 2.0
height = 1.0
[time]
end = 2.0
[[water]]
min = [0.2, 0.0]
max = [2.0, 0.5]
[[wall]]
min = [0.1, 0.0]
max = [0.2, 0.8]
[wall.translation]
law = "file"
direction = [1.0, 0.0]
file = "ntnu_flume2025_1102.csv"
time_column = "Time [s]"
column = "WM_Position [m]"
time_offset = -20.8
)";
  const Case c = load_case_file(dir / "case.toml");
  ASSERT_TRUE(c.walls[0].translation.series);
  EXPECT_NEAR(c.walls[0].translation.series->times.front(), 17.8 - 20.8, 1e-12);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace sluice
