// The wall function (physics/wall_friction.hpp): the law of the wall's friction velocity, and the
// force it puts on the water beside a wall.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "sluice/geometry/box.hpp"
#include "sluice/geometry/polygon.hpp"
#include "sluice/physics/wall_friction.hpp"

using namespace sluice;

namespace {
constexpr double nu = 1e-6;  // water, m^2/s
constexpr double kappa = 0.41, log_e = 9.793;

// u at distance y of the law of the wall with friction velocity u_tau: the sublayer's u+ = y+ below
// y+ = 11.53, the log law above.
double law_of_the_wall(double u_tau, double y) {
  const double y_plus = y * u_tau / nu;
  return y_plus <= 11.53 ? u_tau * y_plus : u_tau * std::log(log_e * y_plus) / kappa;
}
}  // namespace

TEST(FrictionVelocity, InvertsTheLawOfTheWallInTheSublayerAndTheLogLayer) {
  // y+ from 0.5 (sublayer) to 10^5 (log layer), at water's viscosity.
  for (const double u_tau : {0.001, 0.01, 0.05, 0.2}) {
    for (const double y : {1e-4, 1e-3, 7.5e-3, 3e-2}) {
      const double u = law_of_the_wall(u_tau, y);
      EXPECT_NEAR(friction_velocity(u, y, nu), u_tau, 1e-9 * u_tau) << "u_tau " << u_tau << ", y " << y;
    }
  }
  EXPECT_EQ(friction_velocity(0.0, 1e-3, nu), 0.0);
}

TEST(FrictionVelocity, IsContinuousAtTheSublayersEdge) {
  // At y+ = 11.53 the two laws give the same u within 0.1 %, so the stress does not jump there.
  const double y = 1e-3, edge = 11.53;
  const double u_tau = edge * nu / y;
  const double u_sub = u_tau * edge, u_log = u_tau * std::log(log_e * edge) / kappa;
  EXPECT_NEAR(u_log / u_sub, 1.0, 1e-3);
  EXPECT_NEAR(friction_velocity(0.999 * u_sub, y, nu), friction_velocity(1.001 * u_sub, y, nu), 2e-3 * u_tau);
}

TEST(WallFriction, AWaterLayerOnALogLawProfileFeelsItsWallStress) {
  // Water on a lattice over a floor at y = 0 (first row at dx/2, as mDBC walls hold it), moving along
  // x with the law of the wall's profile for u_tau: every particle's estimate is u_tau, so the force
  // on the layer is rho u_tau^2 per unit of floor, to the accuracy of sum_i V 2 W1(y_i) = 1.
  const double dx = 0.01, h = 1.3 * dx, rho = 1000.0, u_tau = 0.05;
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon::box({-1.0, -0.1}, {2.0, 0.0}))};
  Particles<2> p;
  const int columns = 50, rows = 10;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) {
      const double y = (j + 0.5) * dx;
      p.add({(i + 0.5) * dx, y}, Kind::fluid, rho);
      p.velocity[0].back() = law_of_the_wall(u_tau, y);
    }
  p.add({0.2, -0.5 * dx}, Kind::wall, rho);  // a wall particle: untouched
  for (auto& a : p.acceleration) a.assign(p.size(), 0.0);
  const WallFrictionSettings settings{nu, h, dx};
  // Rows up to 2h = 2.6 dx feel it: three of ten.
  EXPECT_EQ(add_wall_friction(p, solids, settings, 2).felt, static_cast<std::size_t>(3 * columns));
  double force = 0.0;  // per unit depth, along x
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p.acceleration[1][i], 0.0, 1e-12 * std::abs(p.acceleration[0][i]) + 1e-300);
    if (p.kind[i] == Kind::fluid) {
      EXPECT_LE(p.acceleration[0][i], 0.0);  // against the flow
      force += rho * dx * dx * p.acceleration[0][i];
    }
  }
  EXPECT_EQ(p.acceleration[0].back(), 0.0);
  const double length = columns * dx;
  std::printf("force / (rho u_tau^2 L) = %.5f\n", force / (-rho * u_tau * u_tau * length));
  EXPECT_NEAR(force / (-rho * u_tau * u_tau * length), 1.0, 0.01);
}

TEST(WallFriction, ActsAlongEachWallAndNotAcrossIt) {
  // A 3D corner: floor z < 0 and side wall x < 0. A particle near both, moving along y and into the
  // floor, is slowed along y by both walls; its motion across the floor is not the friction's.
  const double dx = 0.01, h = 1.3 * dx;
  const Solids<3> solids = {std::make_shared<Box<3>>(Vec<3>{-0.1, -0.1, -0.1}, Vec<3>{1.0, 1.0, 0.0}),
                            std::make_shared<Box<3>>(Vec<3>{-0.1, -0.1, 0.0}, Vec<3>{0.0, 1.0, 1.0})};
  Particles<3> p;
  p.add({0.5 * dx, 0.5, 0.5 * dx}, Kind::fluid, 1000.0);   // in the corner
  p.add({0.5, 0.5, 0.5 * dx}, Kind::fluid, 1000.0);        // on the floor only
  p.add({0.5, 0.5, 3.0 * h}, Kind::fluid, 1000.0);         // beyond 2h of any wall
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.velocity[1][i] = 1.0;
    p.velocity[2][i] = -0.5;
  }
  for (auto& a : p.acceleration) a.assign(p.size(), 0.0);
  const WallFrictionResult result = add_wall_friction(p, solids, WallFrictionSettings{nu, h, dx}, 1);
  EXPECT_EQ(result.felt, 2u);
  // The time step sees the largest acceleration among them: the corner particle's, two walls' worth.
  double corner = 0.0;
  for (int d = 0; d < 3; ++d) corner += p.acceleration[d][0] * p.acceleration[d][0];
  EXPECT_GT(result.max_acceleration, 0.0);
  EXPECT_DOUBLE_EQ(result.max_acceleration, std::sqrt(corner));
  // The floor's friction acts along y only; the side wall's along y and z (z is along it).
  EXPECT_LT(p.acceleration[1][1], 0.0);
  EXPECT_EQ(p.acceleration[0][1], 0.0);
  EXPECT_EQ(p.acceleration[2][1], 0.0);
  EXPECT_LT(p.acceleration[1][0], 1.5 * p.acceleration[1][1]);  // two walls, more than one's
  EXPECT_GT(p.acceleration[2][0], 0.0);  // the side wall resists the fall along it
  EXPECT_EQ(p.acceleration[0][0], 0.0);
  for (int d = 0; d < 3; ++d) EXPECT_EQ(p.acceleration[d][2], 0.0);
}

TEST(WallFriction, BoxesAndGeneralShapesGiveTheSameFriction) {
  // A floor as a box (the clamped closest point) and as a polygon with an extra vertex on its top
  // edge (the general closest-point query), with water around a corner of it.
  const double dx = 0.01, h = 1.3 * dx;
  const auto box = std::make_shared<Polygon>(Polygon::box({0.0, -0.1}, {1.0, 0.0}));
  const auto general = std::make_shared<Polygon>(
      Polygon({{0.0, -0.1}, {1.0, -0.1}, {1.0, 0.0}, {0.5, 0.0}, {0.0, 0.0}}));
  ASSERT_TRUE(box->is_box());
  ASSERT_FALSE(general->is_box());
  const auto run = [&](const std::shared_ptr<Polygon>& floor) {
    Particles<2> p;
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j < 4; ++j) {
        p.add({0.9 + (i + 0.5) * dx * 0.7, (j + 0.5) * dx * 0.9 - 0.01}, Kind::fluid, 1000.0);
        p.velocity[0].back() = 0.3 + 0.01 * i;
        p.velocity[1].back() = -0.2 + 0.02 * j;
      }
    for (auto& a : p.acceleration) a.assign(p.size(), 0.0);
    const std::size_t felt = add_wall_friction(p, Solids<2>{floor}, WallFrictionSettings{nu, h, dx}, 1).felt;
    EXPECT_GT(felt, 40u);
    return p.acceleration;
  };
  const auto a = run(box), b = run(general);
  for (int d = 0; d < 2; ++d)
    for (std::size_t i = 0; i < a[d].size(); ++i) EXPECT_NEAR(a[d][i], b[d][i], 1e-9 * (1.0 + std::abs(b[d][i])));
}

TEST(WallFriction, SkipsTheParticlesItIsToldTo) {
  // Another process's ghosts: their accelerations are not read, so the pass leaves them alone.
  const double dx = 0.01, h = 1.3 * dx;
  const Solids<2> solids = {std::make_shared<Polygon>(Polygon::box({-1.0, -0.1}, {2.0, 0.0}))};
  Particles<2> p;
  for (int i = 0; i < 4; ++i) {
    p.add({(i + 0.5) * dx, 0.5 * dx}, Kind::fluid, 1000.0);
    p.velocity[0].back() = 1.0;
  }
  for (auto& a : p.acceleration) a.assign(p.size(), 0.0);
  const std::vector<std::uint8_t> ghost = {0, 1, 0, 1};
  const WallFrictionResult result = add_wall_friction<2>(p, solids, WallFrictionSettings{nu, h, dx}, 2, nullptr, ghost.data());
  EXPECT_EQ(result.felt, 2u);
  EXPECT_LT(p.acceleration[0][0], 0.0);
  EXPECT_EQ(p.acceleration[0][1], 0.0);
  EXPECT_LT(p.acceleration[0][2], 0.0);
  EXPECT_EQ(p.acceleration[0][3], 0.0);
  EXPECT_DOUBLE_EQ(result.max_acceleration, -p.acceleration[0][0]);
}
