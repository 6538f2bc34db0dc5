// Prescribed motion of a rigid body: a law of time for its translation and one for its rotation about
// a fixed axis through a point that moves with the translation. Every law gives its value, velocity
// and acceleration analytically, so the solver never differentiates positions numerically.
//
// A point of the body that was at X at the start is at
//   x(t) = c0 + d(t) + R(theta(t)) (X - c0),
// with c0 the centre of rotation at the start, d(t) the translation, R the rotation by theta about the
// axis a (the z axis in 2D). With r = x - c0 - d:
//   v = d'(t) + theta' a x r,      acc = d''(t) + theta'' a x r + theta'^2 a x (a x r).
// The laws are scalar functions of time (ScalarLaw): a translation is one of them along a direction,
// or one per axis; a rotation is one of them as the angle.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

// A motion law or motion file that cannot be used; the message names what is wrong and what was expected.
class MotionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A law's value and its first two time derivatives at one time.
struct LawValue {
  double value = 0.0, rate = 0.0, acceleration = 0.0;
};

// A scalar function of time with analytic derivatives.
class ScalarLaw {
 public:
  virtual ~ScalarLaw() = default;
  [[nodiscard]] virtual LawValue at(double t) const = 0;
  // Bounds of |value| over [0, end] (used to check at set-up that a body stays in the tank).
  [[nodiscard]] virtual double largest_magnitude(double end) const;
  // A time after which the law takes no value it has not taken before (it holds, or repeats a
  // period): infinity if there is none. What a body sweeps up to this time is all it ever sweeps.
  [[nodiscard]] virtual double settled_after() const = 0;
};

// What a law does after the interval it is given over.
enum class AfterInterval { hold, continue_ };

// Constant rate between `start` and `end`, at rest before and after (holding where it got to).
class LinearLaw final : public ScalarLaw {
 public:
  LinearLaw(double rate, double start, double end);
  [[nodiscard]] LawValue at(double t) const override;
  [[nodiscard]] double settled_after() const override { return end_; }

 private:
  double rate_, start_, end_;
};

// sum_k c_k (t - start)^k for start <= t <= end; before start c_0, at rest; after end it holds the end
// value (at rest) or continues at the end's rate.
class PolynomialLaw final : public ScalarLaw {
 public:
  PolynomialLaw(std::vector<double> coefficients, double start, double end, AfterInterval after);
  [[nodiscard]] LawValue at(double t) const override;
  [[nodiscard]] double settled_after() const override;

 private:
  [[nodiscard]] LawValue polynomial(double tau) const;
  std::vector<double> c_;
  double start_, end_;
  AfterInterval after_;
};

// A sin(2 pi (t - start) / period + phase) - A sin(phase), from `start` on (0 before), times a ramp
// that grows as (1 - cos(pi s)) / 2, s = (t - start) / (ramp_periods period), from 0 to 1 over the
// first ramp_periods periods (none with 0). The value starts at 0, and with the ramp so do its rate
// and acceleration.
class SinusoidalLaw final : public ScalarLaw {
 public:
  SinusoidalLaw(double amplitude, double period, double phase, double start, double ramp_periods);
  [[nodiscard]] LawValue at(double t) const override;
  [[nodiscard]] double largest_magnitude(double end) const override;
  // The ramp and one whole period after it: every value it will take.
  [[nodiscard]] double settled_after() const override { return start_ + (ramp_periods_ + 1.0) * period_; }

 private:
  double amplitude_, period_, phase_, start_, ramp_periods_;
};

// An irregular wave maker's displacement: sum_n A_n sin(omega_n (t - start) + phi_n) from `start` on
// (0 before), times the ramp of SinusoidalLaw, (1 - cos(pi s)) / 2 with s = (t - start) / ramp_time,
// over the first ramp_time seconds. The rate and acceleration are the sums' own derivatives with the
// ramp's. The value, rate and acceleration start at 0 except the acceleration, which starts at
// r''(0) X(start) = pi^2 / (2 ramp_time^2) sum A_n sin(phi_n), and steps by as much at the ramp's end
// (the phases are not shifted to cancel it, which would move the paddle's mean position). Every
// omega_n is a whole multiple of 2 pi / repeat_period, so after the ramp the motion repeats every
// repeat_period.
class SineSumLaw final : public ScalarLaw {
 public:
  struct Term {
    double amplitude = 0.0, omega = 0.0, phase = 0.0;
  };
  SineSumLaw(std::vector<Term> terms, double start, double ramp_time, double repeat_period);
  [[nodiscard]] LawValue at(double t) const override;
  // The ramp and one repeat period after it: every value it will take.
  [[nodiscard]] double settled_after() const override { return start_ + ramp_time_ + repeat_period_; }
  [[nodiscard]] const std::vector<Term>& terms() const { return terms_; }

 private:
  std::vector<Term> terms_;
  double start_, ramp_time_, repeat_period_;
};

// The sum of two laws (a piston's first- and second-order motions): values, rates and accelerations
// add; it settles when both have.
class SumLaw final : public ScalarLaw {
 public:
  SumLaw(std::shared_ptr<const ScalarLaw> a, std::shared_ptr<const ScalarLaw> b) : a_(std::move(a)), b_(std::move(b)) {}
  [[nodiscard]] LawValue at(double t) const override {
    const LawValue x = a_->at(t), y = b_->at(t);
    return {x.value + y.value, x.rate + y.rate, x.acceleration + y.acceleration};
  }
  [[nodiscard]] double largest_magnitude(double end) const override {
    return a_->largest_magnitude(end) + b_->largest_magnitude(end);
  }
  [[nodiscard]] double settled_after() const override { return std::max(a_->settled_after(), b_->settled_after()); }

 private:
  std::shared_ptr<const ScalarLaw> a_, b_;
};

// A flap's angle from the horizontal displacement X(t) of its face at a height `arm` above its hinge:
// -atan(X / arm), so that a positive X swings the top along up x axis (in 2D, about z: towards +x).
class FlapLaw final : public ScalarLaw {
 public:
  FlapLaw(std::shared_ptr<const ScalarLaw> displacement, double arm) : x_(std::move(displacement)), arm_(arm) {}
  [[nodiscard]] LawValue at(double t) const override {
    const LawValue x = x_->at(t);
    const double u = x.value / arm_, du = x.rate / arm_, ddu = x.acceleration / arm_, q = 1.0 / (1.0 + u * u);
    return {-std::atan(u), -du * q, -(ddu * q - 2.0 * u * du * du * q * q)};
  }
  [[nodiscard]] double largest_magnitude(double end) const override {
    return std::atan(x_->largest_magnitude(end) / arm_);
  }
  [[nodiscard]] double settled_after() const override { return x_->settled_after(); }

 private:
  std::shared_ptr<const ScalarLaw> x_;
  double arm_;
};

// Active absorption at a piston (Schaffer & Klopman 2000): its displacement is its target's (the wave
// maker's law; none for an absorber alone) plus a correction X_c driven by the surface measured a
// distance s in front of it. After each observation at time t_n of the elevation eta there (from the
// still level), the correction's rate until the next is
//   U_c = -sqrt(g/h) (e(t_n - s/c) - e_mean) - X_c / tau,     e = eta - eta_target(s, t),
// the shallow-water absorber: a wave arriving at the piston moves its water at -sqrt(g/h) eta along the
// piston's direction, and a piston that moves with it sends nothing back. The error is taken `delay`
// = s/c earlier (c = sqrt(g h)), when the arriving wave passed the gauge on its way to the piston:
// taken when measured, it would lead the piston's water by k s, which at kh = 1.3 and s = 0.1 m alone
// reflects about 16 % of the wave. e_mean, e's mean over about tau (an exponential average), keeps a
// slow change of the mean level from walking the piston away, and -X_c / tau draws it back to its
// target over tau. Between observations the rate is held, so the value is continuous and the
// correction adds no acceleration; |X_c| stays within `limit` (the rate is 0 while it is held there).
// The past errors are kept at `history` times `delay` / (history - 2) apart. The value at any time is a
// function of the observations alone, which a checkpoint keeps (packed(), unpack()).
class AbsorbingLaw final : public ScalarLaw {
 public:
  static constexpr std::size_t history = 10;
  struct State {
    double time = 0.0;        // of the last observation
    double offset = 0.0;      // X_c then
    double rate = 0.0;        // U_c since then
    double mean_error = 0.0;  // e_mean
    double observed = 0.0;    // 1 once the first observation is made (its error starts e_mean)
    double error = 0.0;       // e at the last observation
    double newest = 0.0;      // the time of past[0]
    std::array<double, history> past{};  // e at newest, newest - spacing, ...
  };
  static constexpr std::size_t state_size = 7 + history;
  // `target`, `target_elevation`: laws of time, or null (an absorber alone: a target of rest and still
  // water). `gain`: sqrt(g/h); `delay`: s / sqrt(g h) (s); `time_constant`: tau (s); `limit`: the
  // largest |X_c| (m).
  AbsorbingLaw(std::shared_ptr<const ScalarLaw> target, std::shared_ptr<const ScalarLaw> target_elevation, double gain,
               double delay, double time_constant, double limit);
  [[nodiscard]] LawValue at(double t) const override;
  // The target's and the limit's: the correction may add up to `limit`.
  [[nodiscard]] double largest_magnitude(double end) const override;
  // The target's: the correction's reach is added to the swept space by the limit, not by sampling.
  [[nodiscard]] double settled_after() const override { return target_ ? target_->settled_after() : 0.0; }
  // The elevation measured in front of the piston at time t (at or after the last observation).
  void observe(double t, double elevation);
  [[nodiscard]] double target_elevation(double t) const;
  [[nodiscard]] double limit() const { return limit_; }
  [[nodiscard]] const State& state() const { return state_; }
  // The state as state_size numbers, and back (for a checkpoint).
  [[nodiscard]] std::array<double, state_size> packed() const;
  void unpack(const double* values);

 private:
  [[nodiscard]] double offset_at(double t) const;
  std::shared_ptr<const ScalarLaw> target_, elevation_;
  double gain_, delay_, spacing_, tau_, limit_;
  State state_;
};

// A recorded series (times increasing) interpolated by a natural cubic spline: the value, rate and
// acceleration are continuous, so the walls' acceleration (which mDBC and Adami's walls use) is
// defined everywhere; linear interpolation would make it zero between samples and infinite at them.
// Before the first time the value is the first sample's, at rest; after the last, the last sample's,
// at rest ("hold"). A run that would go past the last time is refused at set-up unless the case
// says to hold.
class TableLaw final : public ScalarLaw {
 public:
  TableLaw(std::vector<double> times, std::vector<double> values);
  [[nodiscard]] LawValue at(double t) const override;
  [[nodiscard]] double largest_magnitude(double end) const override;
  [[nodiscard]] double settled_after() const override { return t_.back(); }
  [[nodiscard]] double first_time() const { return t_.front(); }
  [[nodiscard]] double last_time() const { return t_.back(); }

 private:
  std::vector<double> t_, y_, m_;  // m: the spline's second derivatives at the samples
};

// Reads a motion series from a CSV file with a header line: the columns are chosen by name (as the
// header spells them, e.g. "WM_Position [m]"), the values turned into the body's motion as
// value * scale, at time time + time_offset. Lines starting with '#' are comments. Throws MotionError
// naming the file, the line and what was expected: no such file, unreadable, empty, a column missing
// (listing the header's), a value that is not a finite number, times that do not increase, fewer than
// two rows.
struct MotionSeries {
  std::vector<double> times, values;
};
MotionSeries read_motion_csv(const std::filesystem::path& file, const std::string& time_column,
                             const std::string& value_column, double scale = 1.0, double time_offset = 0.0);
// The same, from the file's text (`name` names it in messages).
MotionSeries parse_motion_csv(const std::string& text, const std::string& name, const std::string& time_column,
                              const std::string& value_column, double scale = 1.0, double time_offset = 0.0);

// A body's prescribed motion: a translation along `direction` by one law, or none; a rotation about
// `axis` (the z axis in 2D; a unit vector in 3D) through `centre` (at the start; it moves with the
// translation) by another law, or none. Either may be absent; with both, the rotation's centre
// translates.
template <int Dim>
struct RigidMotion {
  std::shared_ptr<const ScalarLaw> translation;  // displacement along `direction`
  Vec<Dim> direction{};                          // unit vector
  std::shared_ptr<const ScalarLaw> rotation;     // angle in radians, right-handed about `axis`
  Vec<3> axis{0.0, 0.0, 1.0};                    // unit vector (2D: z)
  Vec<Dim> centre{};                             // centre of rotation at the start
  // An absorbing piston's translation (the same law as `translation`), which the solver feeds with the
  // surface it measures `gauge_distance` in front of the piston's face; null for every other body.
  std::shared_ptr<AbsorbingLaw> absorber;
  double gauge_distance = 0.0;
};

// A body's pose and its rates at one time.
// The pose is the rotation by `angle` about `axis`; the angular velocity is angular_rate along
// rate_axis and the angular acceleration angular_acceleration along acceleration_axis: all three the
// same axis for a rotation about a fixed one, each its own for a floating body turning freely in 3D.
template <int Dim>
struct BodyState {
  Vec<Dim> displacement{}, velocity{}, acceleration{};  // of the centre of rotation from its start
  double angle = 0.0, angular_rate = 0.0, angular_acceleration = 0.0;
  Vec<3> axis{0.0, 0.0, 1.0};
  Vec<3> rate_axis{0.0, 0.0, 1.0}, acceleration_axis{0.0, 0.0, 1.0};
  Vec<Dim> centre{};  // the centre of rotation at the start
};

template <int Dim>
BodyState<Dim> body_state(const RigidMotion<Dim>& motion, double t);

// The time after which neither law takes a new value (0 for a body that does not move; infinity if a
// law never settles): a body's poses up to it are all the poses it ever takes.
template <int Dim>
double settled_after(const RigidMotion<Dim>& motion) {
  double t = 0.0;
  if (motion.translation) t = std::max(t, motion.translation->settled_after());
  if (motion.rotation) t = std::max(t, motion.rotation->settled_after());
  return t;
}

// Where a point of the body that was at `start` is, and its velocity and acceleration.
template <int Dim>
struct PointMotion {
  Vec<Dim> position{}, velocity{}, acceleration{};
};
template <int Dim>
PointMotion<Dim> point_motion(const BodyState<Dim>& state, const Vec<Dim>& start);

// The velocity and acceleration of the body point now at `x` (its position is x): no rotation to
// compute, so cheap enough for every wall particle at every evaluation.
template <int Dim>
PointMotion<Dim> motion_at(const BodyState<Dim>& s, const Vec<Dim>& x) {
  Vec<3> r{};
  for (int d = 0; d < Dim; ++d) r[d] = x[d] - s.centre[d] - s.displacement[d];
  const auto cross = [](const Vec<3>& a, const Vec<3>& b) -> Vec<3> {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const Vec<3> ar = cross(s.rate_axis, r);
  const Vec<3> aar = cross(s.rate_axis, ar);
  const Vec<3> br = cross(s.acceleration_axis, r);
  PointMotion<Dim> m;
  m.position = x;
  for (int d = 0; d < Dim; ++d) {
    m.velocity[d] = s.velocity[d] + s.angular_rate * ar[d];
    m.acceleration[d] = s.acceleration[d] + s.angular_acceleration * br[d] + s.angular_rate * s.angular_rate * aar[d];
  }
  return m;
}

// The inverse: the start position of the body point now at `x` (to query a solid's geometry, given
// at the start, at the body's current pose).
template <int Dim>
Vec<Dim> to_start(const BodyState<Dim>& state, const Vec<Dim>& x);
// A direction (a surface normal) turned with the body from the start to now.
template <int Dim>
Vec<Dim> rotate_to_now(const BodyState<Dim>& state, const Vec<Dim>& direction);

}  // namespace sluice
