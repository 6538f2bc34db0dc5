// The rigid-body dynamics of a floating body: its centre of gravity moved by Newton's second law and
// its orientation, a unit quaternion, turned by Euler's equations with the gyroscopic term,
//   M a = F,     I alpha = M_G - omega x (I omega),     I = R I_body R^T,
// in the case's (world) axes, with F the water's force on the body's particles, gravity, a constant
// force and the springs and dampers, and M_G the moments about the centre of gravity. A locked degree
// of freedom keeps its start value: its acceleration is 0, and for a locked rotation the constraint's
// moment takes up what the free rotations do not (the rows of the locked axes are replaced by
// alpha_k = 0). In 2D the body has x, y and rz; z, rx and ry are locked.
//
// The solver advances the state with the water's integrator (integrate/integrators.hpp), the same
// stages at the same times: euler(); predict() and correct() (the midpoint); kick_drift() and
// final_kick() (the leapfrog, whose accelerations of a step's end are carried into the next). The
// orientation is advanced by the exact rotation over a stage, q <- exp(omega dt / 2) q.
#pragma once

#include <array>
#include <cstddef>

#include "sluice/case/case.hpp"
#include "sluice/geometry/mass_properties.hpp"
#include "sluice/geometry/motion.hpp"

namespace sluice {

struct Quaternion {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
};

// What the body is and what holds it; fixed for a run.
struct FloatingModel {
  int dimension = 2;
  double mass = 0.0;
  Vec3 start_centre{};                  // the centre of gravity at the start
  std::array<double, 6> inertia{};      // about it, in the start pose's axes: xx, yy, zz, xy, xz, yz
  std::array<bool, 6> free{};           // x, y, z, rx, ry, rz
  std::array<double, 6> stiffness{}, damping{}, anchor{};  // a rotation's anchor in radians
  Vec3 gravity{}, force{}, moment{};
};

// The model of a floating wall from its case: the mass, centre of gravity and inertia the case gives,
// or its shape's at uniform density (`shape`), and gravity.
FloatingModel floating_model(const FloatingSpec& spec, const MassProperties& shape, int dimension, const Vec3& gravity);

// Where the body is and how it moves, and the loads of the last evaluation.
struct FloatingState {
  Vec3 centre{}, velocity{};
  Quaternion orientation{};
  Vec3 omega{};                               // angular velocity, world axes (rad/s)
  Vec3 acceleration{}, angular_acceleration{};  // of the last evaluation's loads
  Vec3 water_force{}, water_moment{};         // the water's, of the last evaluation (moment about the centre)
  Vec3 contact_force{}, contact_moment{};     // the contacts', likewise
  static constexpr std::size_t packed_size = 31;
};

class FloatingBody {
 public:
  FloatingBody() = default;
  // At rest at the start pose, or with the case's initial velocities (`spec`).
  FloatingBody(FloatingModel model, const FloatingSpec& spec);

  [[nodiscard]] const FloatingModel& model() const { return model_; }
  [[nodiscard]] const FloatingState& state() const { return state_; }

  // The water's force and moment (about the centre of gravity) on the body in its current state, and
  // its contacts' with other solids: its accelerations follow.
  void set_load(const Vec3& water_force, const Vec3& water_moment, const Vec3& contact_force = {},
                const Vec3& contact_moment = {});

  // Forward Euler with the accelerations of the current state.
  void euler(double dt);
  // The midpoint rule: predict() saves the state and advances it by dt/2 with its accelerations;
  // correct() advances the saved state by dt with those of the predicted one.
  void predict(double dt);
  void correct(double dt);
  // The leapfrog: kick_drift() gives v(n+1/2) = v + dt/2 a, x(n+1) = x + dt v(n+1/2) and the predicted
  // v* = v(n+1/2) + dt/2 a; final_kick(), after set_load at x(n+1), v(n+1) = v* + dt/2 (a(n+1) - a(n)).
  void kick_drift(double dt);
  void final_kick(double dt);

  // The pose and rates as the walls use them (geometry/motion.hpp).
  template <int Dim>
  [[nodiscard]] BodyState<Dim> pose() const;

  // The springs' and the dampers' forces and moments (about the centre of gravity) now.
  struct Restraint {
    Vec3 spring_force{}, spring_moment{}, damper_force{}, damper_moment{};
  };
  [[nodiscard]] Restraint restraint() const;
  // The rotation vector of the orientation (axis times angle, rad): about z in 2D, the angle itself.
  [[nodiscard]] Vec3 rotation_vector() const;
  // Roll, pitch and yaw (rad): the rotations about x, then y, then z (z-y-x Tait-Bryan angles) that
  // give the orientation.
  [[nodiscard]] Vec3 roll_pitch_yaw() const;

  [[nodiscard]] std::array<double, FloatingState::packed_size> packed() const;
  void unpack(const double* values);

 private:
  void accelerate();
  static void drift(FloatingState& s, const FloatingState& from, const Vec3& velocity, const Vec3& omega, double dt);

  FloatingModel model_;
  FloatingState state_, start_;
};

}  // namespace sluice
