// Floating bodies: the shapes' mass properties against closed forms, the rigid-body dynamics
// (geometry/floating_body.hpp) against the mechanics it must keep — free fall, a spring's period,
// the torque-free top's angular momentum and energy, locked degrees of freedom — and the case's
// [wall.floating] keys and their refusals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "sluice/case/case_error.hpp"
#include "sluice/case/load.hpp"
#include "sluice/geometry/floating_body.hpp"
#include "sluice/geometry/mass_properties.hpp"

namespace sluice {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(MassProperties, ABoxsVolumeCentroidAndInertia) {
  Region box;
  box.min = {1.0, 2.0, 3.0};
  box.max = {1.4, 2.2, 4.0};
  const MassProperties m3 = mass_properties(box, 3);
  EXPECT_NEAR(m3.volume, 0.4 * 0.2 * 1.0, 1e-15);
  EXPECT_NEAR(m3.centroid[0], 1.2, 1e-15);
  EXPECT_NEAR(m3.centroid[2], 3.5, 1e-15);
  EXPECT_NEAR(m3.inertia[0], m3.volume * (0.04 + 1.0) / 12.0, 1e-15);
  EXPECT_NEAR(m3.inertia[2], m3.volume * (0.16 + 0.04) / 12.0, 1e-15);
  const MassProperties m2 = mass_properties(box, 2);
  EXPECT_NEAR(m2.volume, 0.08, 1e-15);
  EXPECT_NEAR(m2.inertia[2], 0.08 * (0.16 + 0.04) / 12.0, 1e-15);
}

// A polygon's area, centroid and polar moment: a rectangle in either orientation is the box; a right
// triangle has its centroid at a third of its legs and J = A (a^2 + b^2) / 18 about it.
TEST(MassProperties, APolygonsAreaCentroidAndPolarMoment) {
  Region rect;
  rect.shape = Shape::polygon;
  rect.points = {{1.0, 2.0}, {1.4, 2.0}, {1.4, 2.2}, {1.0, 2.2}};
  Region box;
  box.min = {1.0, 2.0, 0.0};
  box.max = {1.4, 2.2, 0.0};
  const MassProperties b = mass_properties(box, 2);
  for (int turn = 0; turn < 2; ++turn) {
    if (turn == 1) std::reverse(rect.points.begin(), rect.points.end());
    const MassProperties p = mass_properties(rect, 2);
    EXPECT_NEAR(p.volume, b.volume, 1e-14);
    EXPECT_NEAR(p.centroid[0], b.centroid[0], 1e-14);
    EXPECT_NEAR(p.centroid[1], b.centroid[1], 1e-14);
    EXPECT_NEAR(p.inertia[2], b.inertia[2], 1e-14);
  }
  Region tri;
  tri.shape = Shape::polygon;
  tri.points = {{0.0, 0.0}, {3.0, 0.0}, {0.0, 2.0}};
  const MassProperties t = mass_properties(tri, 2);
  EXPECT_NEAR(t.volume, 3.0, 1e-14);
  EXPECT_NEAR(t.centroid[0], 1.0, 1e-14);
  EXPECT_NEAR(t.centroid[1], 2.0 / 3.0, 1e-14);
  EXPECT_NEAR(t.inertia[2], 3.0 * (9.0 + 4.0) / 18.0, 1e-13);
}

// A closed mesh of a box (12 triangles, outward) has the box's properties, moved off the origin.
TEST(MassProperties, AClosedMeshIsTheBoxItBounds) {
  auto mesh = std::make_shared<TriangleMesh>();
  const Vec3 lo{0.5, -1.0, 2.0}, hi{1.5, 0.0, 2.5};
  for (int k = 0; k < 8; ++k) mesh->vertices.push_back({k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]});
  // Faces of the cube's corners (bit 0 x, bit 1 y, bit 2 z), counter-clockwise from outside.
  mesh->triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                     {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  Region r;
  r.shape = Shape::mesh;
  r.mesh = mesh;
  Region box;
  box.min = lo;
  box.max = hi;
  const MassProperties m = mass_properties(r, 3), b = mass_properties(box, 3);
  EXPECT_NEAR(m.volume, b.volume, 1e-14);
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(m.centroid[d], b.centroid[d], 1e-14);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(m.inertia[k], b.inertia[k], 1e-13) << k;
}

FloatingModel model(int dimension, double mass, std::array<double, 6> inertia) {
  FloatingModel m;
  m.dimension = dimension;
  m.mass = mass;
  m.inertia = inertia;
  m.free = {true, true, dimension == 3, dimension == 3, dimension == 3, true};
  return m;
}

enum class Scheme { euler, midpoint, leapfrog };

// n steps of dt with no water: the loads are zero at every evaluation.
void advance(FloatingBody& b, Scheme s, double dt, int n) {
  const Vec3 zero{};
  b.set_load(zero, zero);
  for (int i = 0; i < n; ++i) {
    switch (s) {
      case Scheme::euler:
        b.euler(dt);
        b.set_load(zero, zero);
        break;
      case Scheme::midpoint:
        b.predict(dt);
        b.set_load(zero, zero);
        b.correct(dt);
        b.set_load(zero, zero);
        break;
      case Scheme::leapfrog:
        b.kick_drift(dt);
        b.set_load(zero, zero);
        b.final_kick(dt);
        break;
    }
  }
}

// Under gravity alone the centre of gravity falls as g t^2 / 2: the midpoint rule and the leapfrog
// are exact for a constant acceleration (to rounding), Euler lags by g t dt / 2.
TEST(FloatingBody, FallsFreelyUnderGravity) {
  for (Scheme s : {Scheme::euler, Scheme::midpoint, Scheme::leapfrog}) {
    FloatingModel m = model(2, 3.0, {1.0, 1.0, 1.0, 0.0, 0.0, 0.0});
    m.gravity = {0.0, -9.81, 0.0};
    m.start_centre = {1.0, 2.0, 0.0};
    FloatingBody b(m, FloatingSpec{});
    const double dt = 1e-3;
    advance(b, s, dt, 1000);
    const double exact = 2.0 - 0.5 * 9.81;
    if (s == Scheme::euler) EXPECT_NEAR(b.state().centre[1], exact + 0.5 * 9.81 * dt, 1e-9);
    else EXPECT_NEAR(b.state().centre[1], exact, 1e-11);
    EXPECT_NEAR(b.state().velocity[1], -9.81, 1e-11);
    EXPECT_EQ(b.state().centre[0], 1.0);
  }
}

// A mass on a spring k with a damper c oscillates at omega_d = sqrt(k/m - (c/2m)^2) about its anchor
// and decays as exp(-c t / 2m): after 5 periods, within 1e-4 of the closed form for the two
// second-order schemes.
TEST(FloatingBody, ASpringAndDamperGiveTheDampedOscillatorsMotion) {
  for (Scheme s : {Scheme::midpoint, Scheme::leapfrog}) {
    FloatingModel m = model(2, 2.0, {1.0, 1.0, 1.0, 0.0, 0.0, 0.0});
    m.stiffness[0] = 50.0;
    m.damping[0] = 0.4;
    m.anchor[0] = 1.0;
    m.start_centre = {1.1, 0.0, 0.0};
    FloatingBody b(m, FloatingSpec{});
    const double wd = std::sqrt(25.0 - 0.01), period = 2.0 * kPi / wd;
    const int n = 20000;
    const double dt = 5.0 * period / n;
    advance(b, s, dt, n);
    const double t = n * dt;
    // x(t) = A e^{-zeta t} (cos wd t + zeta/wd sin wd t), zeta = c / 2m = 0.1.
    const double exact = 1.0 + 0.1 * std::exp(-0.1 * t) * (std::cos(wd * t) + 0.1 / wd * std::sin(wd * t));
    EXPECT_NEAR(b.state().centre[0], exact, 1e-4);
    // The restraint reports the spring's and damper's forces.
    EXPECT_NEAR(b.restraint().spring_force[0], -50.0 * (b.state().centre[0] - 1.0), 1e-12);
    EXPECT_NEAR(b.restraint().damper_force[0], -0.4 * b.state().velocity[0], 1e-12);
  }
}

// A free asymmetric top (Ixx < Iyy < Izz) spun mostly about its middle axis tumbles (the middle axis
// is unstable), yet its angular momentum I omega, in the world's axes, and its energy stay: to 1e-5
// over 20000 steps (2 s) with the leapfrog. Without Euler's gyroscopic term, I alpha = M alone, the turning
// body's momentum would not stay (the check fails by orders of magnitude).
TEST(FloatingBody, AFreeTopKeepsItsAngularMomentumAndEnergy) {
  FloatingModel m = model(3, 1.0, {1.0, 2.0, 3.0, 0.0, 0.0, 0.0});
  FloatingSpec spec;
  spec.angular_velocity = {0.5 * 180.0 / kPi, 10.0 * 180.0 / kPi, 0.2 * 180.0 / kPi};
  FloatingBody b(m, spec);
  const auto momentum = [&](const FloatingBody& body) {
    const FloatingState& s = body.state();
    // L = R I R^T omega, with R from the quaternion.
    const Quaternion& q = s.orientation;
    const double R[3][3] = {{1 - 2 * (q.y * q.y + q.z * q.z), 2 * (q.x * q.y - q.w * q.z), 2 * (q.x * q.z + q.w * q.y)},
                            {2 * (q.x * q.y + q.w * q.z), 1 - 2 * (q.x * q.x + q.z * q.z), 2 * (q.y * q.z - q.w * q.x)},
                            {2 * (q.x * q.z - q.w * q.y), 2 * (q.y * q.z + q.w * q.x), 1 - 2 * (q.x * q.x + q.y * q.y)}};
    const double I[3] = {1.0, 2.0, 3.0};
    double body_w[3] = {}, L[3] = {};
    for (int k = 0; k < 3; ++k)
      for (int r = 0; r < 3; ++r) body_w[k] += R[r][k] * s.omega[r];  // R^T omega
    double energy = 0.0;
    for (int k = 0; k < 3; ++k) energy += 0.5 * I[k] * body_w[k] * body_w[k];
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) L[r] += R[r][k] * I[k] * body_w[k];
    return std::array<double, 4>{L[0], L[1], L[2], energy};
  };
  const auto start = momentum(b);
  // The body's own y axis, R e_y, seen from the world's y: 1 at the start, negative once it has flipped.
  double lowest = 1.0;
  const Vec3 zero{};
  b.set_load(zero, zero);
  for (int i = 0; i < 20000; ++i) {
    b.kick_drift(1e-4);
    b.set_load(zero, zero);
    b.final_kick(1e-4);
    const Quaternion& q = b.state().orientation;
    lowest = std::min(lowest, 1 - 2 * (q.x * q.x + q.z * q.z));
  }
  const auto end = momentum(b);
  const double size = std::hypot(start[0], start[1], start[2]);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(end[k], start[k], 1e-5 * size) << k;
  EXPECT_NEAR(end[3], start[3], 1e-5 * start[3]);
  // It tumbled: the middle axis turned over (the test has seen the gyroscopic term at work).
  EXPECT_LT(lowest, -0.5);
}

// Locked degrees of freedom keep their start values whatever the loads: heave only in 2D, and in 3D
// a body free to turn about x alone takes no rotation about y and z from a moment along them.
TEST(FloatingBody, LockedDegreesOfFreedomHoldTheirStart) {
  FloatingModel m = model(2, 1.0, {1.0, 1.0, 1.0, 0.0, 0.0, 0.0});
  m.free[0] = m.free[5] = false;
  m.gravity = {0.0, -9.81, 0.0};
  FloatingBody b(m, FloatingSpec{});
  b.set_load({5.0, 1.0, 0.0}, {0.0, 0.0, 2.0});
  b.kick_drift(0.01);
  b.set_load({5.0, 1.0, 0.0}, {0.0, 0.0, 2.0});
  b.final_kick(0.01);
  EXPECT_EQ(b.state().centre[0], 0.0);
  EXPECT_EQ(b.state().omega[2], 0.0);
  EXPECT_NE(b.state().centre[1], 0.0);

  FloatingModel r = model(3, 1.0, {1.0, 2.0, 3.0, 0.2, 0.1, 0.3});
  r.free[4] = r.free[5] = false;
  FloatingBody t(r, FloatingSpec{});
  t.set_load({}, {1.0, 1.0, 1.0});
  t.euler(0.01);
  EXPECT_EQ(t.state().omega[1], 0.0);
  EXPECT_EQ(t.state().omega[2], 0.0);
  // About x alone: I_xx alpha_x = M_x.
  EXPECT_NEAR(t.state().omega[0], 0.01 * 1.0 / 1.0, 1e-15);
}

// The state round-trips through its packed numbers (the checkpoint's) bit for bit.
TEST(FloatingBody, ItsPackedStateRoundTrips) {
  FloatingModel m = model(3, 2.0, {1.0, 2.0, 3.0, 0.0, 0.0, 0.0});
  m.gravity = {0.0, 0.0, -9.81};
  FloatingSpec spec;
  spec.angular_velocity = {10.0, 20.0, 30.0};
  FloatingBody b(m, spec);
  advance(b, Scheme::leapfrog, 1e-3, 10);
  FloatingBody c(m, FloatingSpec{});
  const auto packed = b.packed();
  c.unpack(packed.data());
  EXPECT_EQ(c.packed(), packed);
  const BodyState<3> pb = b.pose<3>(), pc = c.pose<3>();
  EXPECT_EQ(pb.angle, pc.angle);
  EXPECT_EQ(pb.displacement, pc.displacement);
}

// The model from a case: mass from the density and the shape, the inertia from the shape, a radius of
// gyration or the case's value, rotations' anchors in radians.
TEST(FloatingBody, ItsModelComesFromTheCase) {
  Region box;
  box.min = {0.0, 0.0, 0.0};
  box.max = {0.4, 0.2, 0.0};
  FloatingSpec spec;
  spec.density = 500.0;
  const FloatingModel a = floating_model(spec, mass_properties(box, 2), 2, {0.0, -9.81, 0.0});
  EXPECT_NEAR(a.mass, 40.0, 1e-12);
  EXPECT_NEAR(a.inertia[2], 40.0 * (0.16 + 0.04) / 12.0, 1e-12);
  EXPECT_NEAR(a.start_centre[0], 0.2, 1e-15);
  spec.radius_of_gyration = {0.144};
  spec.centre_of_gravity = {0.2, 0.05};
  spec.anchor = {0.0, 0.0, 90.0};
  const FloatingModel b = floating_model(spec, mass_properties(box, 2), 2, {0.0, -9.81, 0.0});
  EXPECT_NEAR(b.inertia[2], 40.0 * 0.144 * 0.144, 1e-12);
  EXPECT_EQ(b.start_centre[1], 0.05);
  EXPECT_NEAR(b.anchor[5], kPi / 2.0, 1e-15);
  // Moved off the centroid, the shape's inertia gains m d^2.
  spec.radius_of_gyration.clear();
  const FloatingModel c = floating_model(spec, mass_properties(box, 2), 2, {0.0, -9.81, 0.0});
  EXPECT_NEAR(c.inertia[2], a.inertia[2] + 40.0 * 0.05 * 0.05, 1e-12);
}

// The case's [wall.floating] table: read, and refused with a message naming what is wrong.
std::string floating_case(const std::string& floating, const std::string& wall_extra = "") {
  return R"(
[domain]
dx = 0.02
[tank]
width = 1.0
height = 1.0
[time]
end = 0.1
[[water]]
min = [0.0, 0.0]
max = [1.0, 0.5]
[[wall]]
name = "box"
min = [0.4, 0.4]
max = [0.6, 0.6]
)" + wall_extra + "[wall.floating]\n" + floating;
}

std::string refusal(const std::string& text) {
  try {
    parse_case(text, "float.toml");
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}

TEST(FloatingCase, TheKeysAreRead) {
  const Case c = parse_case(floating_case(R"(mass = 20.0
centre_of_gravity = [0.5, 0.45]
radius_of_gyration = [0.08]
lock = ["x"]
stiffness = [0.0, 0.0, 3.0]
damping = [0.0, 1.0, 0.0]
anchor = [0.0, 0.0, 0.0]
)"),
                            "float.toml");
  ASSERT_EQ(c.walls.size(), 1u);
  EXPECT_TRUE(c.walls[0].floats);
  EXPECT_TRUE(c.walls[0].moves());
  EXPECT_EQ(c.walls[0].floating.mass, 20.0);
  EXPECT_EQ(c.walls[0].floating.lock, std::vector<std::string>{"x"});
  EXPECT_EQ(c.walls[0].floating.stiffness[2], 3.0);
}

TEST(FloatingCase, BadInputIsRefusedWithWhatWasExpected) {
  const auto says = [](const std::string& text, const std::string& expected) {
    const std::string message = refusal(text);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
  };
  says(floating_case("mass = 1.0\ndensity = 500.0\n"), "expected one of them");
  says(floating_case(""), "expected one of them");
  says(floating_case("mass = 1.0\ninertia = [-2.0]\n"), "is not positive");
  says(floating_case("mass = 1.0\nlock = [\"heave\"]\n"), "unknown entry \"heave\"");
  says(floating_case("mass = 1.0\nlock = [\"rx\"]\n"), "\"rx\" is not a degree of freedom of a 2D body");
  says(floating_case("mass = 1.0\nstiffness = [0.0, 60.0, 0.0]\n"), "the spring on y (stiffness 60) has no anchor");
  says(floating_case("mass = 1.0\nstiffness = [60.0]\n"), "stiffness has 1 value; expected 3 in a 2D case");
  says(floating_case("mass = 1.0\nmasss = 2\n"), "unknown key 'masss'");
  says(floating_case("mass = 1.0\n", "[wall.translation]\nlaw = \"linear\"\nspeed = 1.0\nend = 1.0\ndirection = [1.0, 0.0]\n"),
       "floats and has a [wall.translation] law");
}

}  // namespace
}  // namespace sluice
