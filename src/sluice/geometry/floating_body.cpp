#include "sluice/geometry/floating_body.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace sluice {

namespace {

constexpr double kRadian = std::numbers::pi / 180.0;

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

using Mat3 = std::array<std::array<double, 3>, 3>;

Mat3 matrix_of(const std::array<double, 6>& t) {
  return {{{t[0], t[3], t[4]}, {t[3], t[1], t[5]}, {t[4], t[5], t[2]}}};
}

Vec3 times(const Mat3& m, const Vec3& v) {
  Vec3 out{};
  for (int r = 0; r < 3; ++r) out[r] = m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
  return out;
}

Mat3 rotation_matrix(const Quaternion& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
           {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
           {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

// R I R^T.
Mat3 turned(const Mat3& R, const Mat3& I) {
  Mat3 RI{}, out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) RI[r][c] += R[r][k] * I[k][c];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) out[r][c] += RI[r][k] * R[c][k];
  return out;
}

// A x = b by Gaussian elimination with partial pivoting (A positive definite here).
Vec3 solve(Mat3 A, Vec3 b) {
  for (int c = 0; c < 3; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 3; ++r)
      if (std::abs(A[r][c]) > std::abs(A[pivot][c])) pivot = r;
    std::swap(A[c], A[pivot]);
    std::swap(b[c], b[pivot]);
    for (int r = c + 1; r < 3; ++r) {
      const double f = A[r][c] / A[c][c];
      for (int k = c; k < 3; ++k) A[r][k] -= f * A[c][k];
      b[r] -= f * b[c];
    }
  }
  Vec3 x{};
  for (int r = 2; r >= 0; --r) {
    double s = b[r];
    for (int k = r + 1; k < 3; ++k) s -= A[r][k] * x[k];
    x[r] = s / A[r][r];
  }
  return x;
}

// exp(v / 2) q: q turned by the rotation vector v (world axes), normalised.
Quaternion turn(const Quaternion& q, const Vec3& v) {
  const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (angle == 0.0) return q;
  const double c = std::cos(0.5 * angle), s = std::sin(0.5 * angle) / angle;
  const Quaternion r{c, s * v[0], s * v[1], s * v[2]};
  Quaternion p{r.w * q.w - r.x * q.x - r.y * q.y - r.z * q.z, r.w * q.x + r.x * q.w + r.y * q.z - r.z * q.y,
               r.w * q.y - r.x * q.z + r.y * q.w + r.z * q.x, r.w * q.z + r.x * q.y - r.y * q.x + r.z * q.w};
  const double n = std::sqrt(p.w * p.w + p.x * p.x + p.y * p.y + p.z * p.z);
  p.w /= n, p.x /= n, p.y /= n, p.z /= n;
  return p;
}

}  // namespace

FloatingModel floating_model(const FloatingSpec& spec, const MassProperties& shape, int dimension, const Vec3& gravity) {
  FloatingModel m;
  m.dimension = dimension;
  m.mass = spec.mass > 0.0 ? spec.mass : spec.density * shape.volume;
  m.start_centre = shape.centroid;
  for (std::size_t d = 0; d < spec.centre_of_gravity.size() && d < 3; ++d) m.start_centre[d] = spec.centre_of_gravity[d];
  const std::size_t rotations = dimension == 2 ? 1 : 3;
  if (!spec.inertia.empty()) {
    if (dimension == 2) m.inertia[2] = spec.inertia[0];
    else
      for (std::size_t k = 0; k < spec.inertia.size(); ++k) m.inertia[k] = spec.inertia[k];
  } else if (!spec.radius_of_gyration.empty()) {
    for (std::size_t k = 0; k < rotations; ++k) {
      const double r = spec.radius_of_gyration[k];
      m.inertia[dimension == 2 ? 2 : k] = m.mass * r * r;
    }
  } else {
    // The shape's at uniform density, moved to the centre of gravity (parallel axes).
    const double density = m.mass / shape.volume;
    Vec3 d{};
    for (int k = 0; k < 3; ++k) d[k] = shape.centroid[k] - m.start_centre[k];
    const double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    m.inertia = {density * shape.inertia[0] + m.mass * (d2 - d[0] * d[0]),
                 density * shape.inertia[1] + m.mass * (d2 - d[1] * d[1]),
                 density * shape.inertia[2] + m.mass * (d2 - d[2] * d[2]),
                 density * shape.inertia[3] - m.mass * d[0] * d[1],
                 density * shape.inertia[4] - m.mass * d[0] * d[2],
                 density * shape.inertia[5] - m.mass * d[1] * d[2]};
  }
  if (dimension == 2) {
    // The plane body: only zz counts; the others set so that the locked rows are well posed.
    m.inertia = {m.inertia[2], m.inertia[2], m.inertia[2], 0.0, 0.0, 0.0};
  }
  const std::vector<std::string> dofs = floating_dofs(dimension);
  // The slot of each of the case's degrees of freedom among x, y, z, rx, ry, rz.
  const auto slot = [&](std::size_t k) -> std::size_t { return dimension == 2 && k == 2 ? 5 : k; };
  for (std::size_t k = 0; k < dofs.size(); ++k) {
    const std::size_t s = slot(k);
    m.free[s] = std::find(spec.lock.begin(), spec.lock.end(), dofs[k]) == spec.lock.end();
    const bool rotation = s >= 3;
    if (k < spec.stiffness.size()) m.stiffness[s] = spec.stiffness[k];
    if (k < spec.damping.size()) m.damping[s] = spec.damping[k];
    if (k < spec.anchor.size()) m.anchor[s] = spec.anchor[k] * (rotation ? kRadian : 1.0);
  }
  m.gravity = gravity;
  for (int d = 0; d < dimension; ++d) m.force[d] = spec.force[d];
  if (dimension == 2 && !spec.moment.empty()) m.moment[2] = spec.moment[0];
  if (dimension == 3)
    for (std::size_t k = 0; k < spec.moment.size(); ++k) m.moment[k] = spec.moment[k];
  return m;
}

FloatingBody::FloatingBody(FloatingModel model, const FloatingSpec& spec) : model_(std::move(model)) {
  state_.centre = model_.start_centre;
  for (int d = 0; d < model_.dimension; ++d) state_.velocity[d] = model_.free[d] ? spec.velocity[d] : 0.0;
  if (model_.dimension == 2 && !spec.angular_velocity.empty()) state_.omega[2] = spec.angular_velocity[0] * kRadian;
  if (model_.dimension == 3)
    for (std::size_t k = 0; k < spec.angular_velocity.size(); ++k) state_.omega[k] = spec.angular_velocity[k] * kRadian;
  for (int k = 0; k < 3; ++k)
    if (!model_.free[3 + k]) state_.omega[k] = 0.0;
  start_ = state_;
}

Vec3 FloatingBody::rotation_vector() const {
  const Quaternion& q = state_.orientation;
  if (model_.dimension == 2) return {0.0, 0.0, 2.0 * std::atan2(q.z, q.w)};
  const double s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
  if (s == 0.0) return {};
  // The shorter way round: q and -q are the same orientation.
  const double angle = 2.0 * std::atan2(s, std::abs(q.w)), sign = q.w < 0.0 ? -1.0 : 1.0;
  return {sign * angle * q.x / s, sign * angle * q.y / s, sign * angle * q.z / s};
}

Vec3 FloatingBody::roll_pitch_yaw() const {
  const Quaternion& q = state_.orientation;
  const double roll = std::atan2(2.0 * (q.w * q.x + q.y * q.z), 1.0 - 2.0 * (q.x * q.x + q.y * q.y));
  const double pitch = std::asin(std::clamp(2.0 * (q.w * q.y - q.z * q.x), -1.0, 1.0));
  const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
  return {roll, pitch, yaw};
}

FloatingBody::Restraint FloatingBody::restraint() const {
  Restraint r;
  const Vec3 angle = rotation_vector();
  for (int k = 0; k < 3; ++k) {
    if (model_.free[k]) {
      r.spring_force[k] = -model_.stiffness[k] * (state_.centre[k] - model_.anchor[k]);
      r.damper_force[k] = -model_.damping[k] * state_.velocity[k];
    }
    if (model_.free[3 + k]) {
      r.spring_moment[k] = -model_.stiffness[3 + k] * (angle[k] - model_.anchor[3 + k]);
      r.damper_moment[k] = -model_.damping[3 + k] * state_.omega[k];
    }
  }
  return r;
}

void FloatingBody::set_load(const Vec3& water_force, const Vec3& water_moment, const Vec3& contact_force,
                            const Vec3& contact_moment) {
  state_.water_force = water_force;
  state_.water_moment = water_moment;
  state_.contact_force = contact_force;
  state_.contact_moment = contact_moment;
  accelerate();
}

void FloatingBody::accelerate() {
  const Restraint r = restraint();
  FloatingState& s = state_;
  for (int k = 0; k < 3; ++k) {
    const double f = s.water_force[k] + s.contact_force[k] + model_.mass * model_.gravity[k] + model_.force[k] +
                     r.spring_force[k] + r.damper_force[k];
    s.acceleration[k] = model_.free[k] ? f / model_.mass : 0.0;
  }
  const Mat3 I = turned(rotation_matrix(s.orientation), matrix_of(model_.inertia));
  const Vec3 gyroscopic = cross(s.omega, times(I, s.omega));
  Mat3 A = I;
  Vec3 b{};
  for (int k = 0; k < 3; ++k) {
    b[k] = s.water_moment[k] + s.contact_moment[k] + model_.moment[k] + r.spring_moment[k] + r.damper_moment[k] -
           gyroscopic[k];
    if (model_.free[3 + k]) continue;
    A[k] = {0.0, 0.0, 0.0};
    A[k][k] = 1.0;
    b[k] = 0.0;
  }
  s.angular_acceleration = solve(A, b);
}

void FloatingBody::drift(FloatingState& s, const FloatingState& from, const Vec3& velocity, const Vec3& omega,
                         double dt) {
  for (int k = 0; k < 3; ++k) s.centre[k] = from.centre[k] + dt * velocity[k];
  s.orientation = turn(from.orientation, dt * omega);
}

void FloatingBody::euler(double dt) {
  const FloatingState n = state_;
  drift(state_, n, n.velocity, n.omega, dt);
  state_.velocity = n.velocity + dt * n.acceleration;
  state_.omega = n.omega + dt * n.angular_acceleration;
}

void FloatingBody::predict(double dt) {
  start_ = state_;
  euler(0.5 * dt);
}

void FloatingBody::correct(double dt) {
  const FloatingState half = state_;
  state_ = start_;
  drift(state_, start_, half.velocity, half.omega, dt);
  state_.velocity = start_.velocity + dt * half.acceleration;
  state_.omega = start_.omega + dt * half.angular_acceleration;
  state_.acceleration = half.acceleration;
  state_.angular_acceleration = half.angular_acceleration;
  state_.water_force = half.water_force;
  state_.water_moment = half.water_moment;
  state_.contact_force = half.contact_force;
  state_.contact_moment = half.contact_moment;
}

void FloatingBody::kick_drift(double dt) {
  start_ = state_;
  const double half = 0.5 * dt;
  const Vec3 v_half = state_.velocity + half * state_.acceleration;
  const Vec3 w_half = state_.omega + half * state_.angular_acceleration;
  drift(state_, start_, v_half, w_half, dt);
  state_.velocity = v_half + half * state_.acceleration;
  state_.omega = w_half + half * state_.angular_acceleration;
}

void FloatingBody::final_kick(double dt) {
  const double half = 0.5 * dt;
  state_.velocity = state_.velocity + half * (state_.acceleration - start_.acceleration);
  state_.omega = state_.omega + half * (state_.angular_acceleration - start_.angular_acceleration);
}

template <int Dim>
BodyState<Dim> FloatingBody::pose() const {
  const FloatingState& s = state_;
  BodyState<Dim> b;
  for (int d = 0; d < Dim; ++d) {
    b.centre[d] = model_.start_centre[d];
    b.displacement[d] = s.centre[d] - model_.start_centre[d];
    b.velocity[d] = s.velocity[d];
    b.acceleration[d] = s.acceleration[d];
  }
  const Vec3 z{0.0, 0.0, 1.0};
  if constexpr (Dim == 2) {
    b.axis = b.rate_axis = b.acceleration_axis = z;
    b.angle = rotation_vector()[2];
    b.angular_rate = s.omega[2];
    b.angular_acceleration = s.angular_acceleration[2];
  } else {
    const Quaternion& q = s.orientation;
    const double n = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    b.angle = 2.0 * std::atan2(n, q.w);
    b.axis = n > 0.0 ? Vec3{q.x / n, q.y / n, q.z / n} : z;
    const auto split = [&](const Vec3& v, double& size, Vec3& axis) {
      size = norm(v);
      axis = size > 0.0 ? (1.0 / size) * v : z;
    };
    split(s.omega, b.angular_rate, b.rate_axis);
    split(s.angular_acceleration, b.angular_acceleration, b.acceleration_axis);
  }
  return b;
}

template BodyState<2> FloatingBody::pose<2>() const;
template BodyState<3> FloatingBody::pose<3>() const;

std::array<double, FloatingState::packed_size> FloatingBody::packed() const {
  std::array<double, FloatingState::packed_size> v{};
  std::size_t k = 0;
  const auto put = [&](const Vec3& x) {
    for (double c : x) v[k++] = c;
  };
  put(state_.centre);
  put(state_.velocity);
  v[k++] = state_.orientation.w;
  v[k++] = state_.orientation.x;
  v[k++] = state_.orientation.y;
  v[k++] = state_.orientation.z;
  put(state_.omega);
  put(state_.acceleration);
  put(state_.angular_acceleration);
  put(state_.water_force);
  put(state_.water_moment);
  put(state_.contact_force);
  put(state_.contact_moment);
  return v;
}

void FloatingBody::unpack(const double* values) {
  std::size_t k = 0;
  const auto get = [&](Vec3& x) {
    for (double& c : x) c = values[k++];
  };
  get(state_.centre);
  get(state_.velocity);
  state_.orientation = {values[k], values[k + 1], values[k + 2], values[k + 3]};
  k += 4;
  get(state_.omega);
  get(state_.acceleration);
  get(state_.angular_acceleration);
  get(state_.water_force);
  get(state_.water_moment);
  get(state_.contact_force);
  get(state_.contact_moment);
  start_ = state_;
}

}  // namespace sluice
