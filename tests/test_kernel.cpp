// Kernel facts: normalisation, analytic derivative, compact support, and lattice consistency.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "sluice/physics/kernel.hpp"

using namespace sluice;

template <class K>
class KernelTest : public ::testing::Test {};
using Kernels = ::testing::Types<CubicSpline<2>, WendlandC2<2>>;
TYPED_TEST_SUITE(KernelTest, Kernels);

TYPED_TEST(KernelTest, IntegratesToOneOverItsSupport) {
  const double h = 0.37;
  const TypeParam kernel(h);
  // 2D: integral of W over the plane = integral 2 pi r W(r) dr (midpoint rule, fine).
  const int n = 200000;
  const double rmax = TypeParam::support * h;
  double integral = 0.0;
  for (int k = 0; k < n; ++k) {
    const double r = (k + 0.5) * rmax / n;
    integral += 2.0 * std::numbers::pi * r * kernel.value(r) * rmax / n;
  }
  EXPECT_NEAR(integral, 1.0, 1e-9);
}

TYPED_TEST(KernelTest, DerivativeMatchesFiniteDifference) {
  const double h = 0.5;
  const TypeParam kernel(h);
  for (double q = 0.05; q < 1.99; q += 0.0731) {
    const double r = q * h;
    const double eps = 1e-6 * h;
    const double numeric = (kernel.value(r + eps) - kernel.value(r - eps)) / (2 * eps);
    EXPECT_NEAR(kernel.derivative(r), numeric, 1e-6 * std::abs(kernel.value(0.0)) / h) << "q = " << q;
  }
}

TYPED_TEST(KernelTest, CompactSupportAndShape) {
  const double h = 1.3;
  const TypeParam kernel(h);
  EXPECT_EQ(kernel.value(2.0 * h), 0.0);
  EXPECT_EQ(kernel.value(2.5 * h), 0.0);
  EXPECT_EQ(kernel.derivative(2.0 * h), 0.0);
  EXPECT_EQ(kernel.derivative(0.0), 0.0);
  EXPECT_GT(kernel.value(1.999 * h), 0.0);
  for (double q = 0.01; q < 2.0; q += 0.01) {
    EXPECT_LE(kernel.derivative(q * h), 0.0) << "W must not increase with r, q = " << q;
    EXPECT_LT(kernel.value(q * h), kernel.value(0.0));
  }
}

// On a uniform lattice, sum_j V_j W_ij ~ 1 and sum_j V_j grad W_ij = 0 (by symmetry, to round-off).
TYPED_TEST(KernelTest, LatticeSumsAreConsistent) {
  const double dx = 0.1, h = 1.3 * dx;
  const TypeParam kernel(h);
  double sum_w = 0.0, grad_x = 0.0, grad_y = 0.0;
  // Moment: sum_j V_j (x_j - x_i) grad_i W_ij = 1: the SPH gradient of f(x) = x.
  double moment_xx = 0.0;
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) {
      const double x = i * dx, y = j * dx, r = std::hypot(x, y);
      sum_w += dx * dx * kernel.value(r);
      if (r == 0.0) continue;
      const double dW = kernel.derivative(r);
      grad_x += dx * dx * dW * (-x) / r;
      grad_y += dx * dx * dW * (-y) / r;
      moment_xx += dx * dx * x * dW * (-x) / r;
    }
  EXPECT_NEAR(sum_w, 1.0, 0.02);
  EXPECT_NEAR(grad_x, 0.0, 1e-12);
  EXPECT_NEAR(grad_y, 0.0, 1e-12);
  EXPECT_NEAR(moment_xx, 1.0, 0.03);
}

// The pair terms use F = dW/dr / r; gradient_factor writes it without the division where it can.
// It must equal derivative(r) / r inside the support (both pieces of the cubic spline), be exactly
// zero from the support on (padding and masked lanes rely on it), and stay finite as r -> 0.
TYPED_TEST(KernelTest, GradientFactorIsDerivativeOverR) {
  const double h = 0.37;
  const TypeParam kernel(h);
  const double support = TypeParam::support * h;
  for (int k = 1; k < 400; ++k) {
    const double r = k * support / 400.0;
    const double expected = kernel.derivative(r) / r;
    EXPECT_NEAR(kernel.gradient_factor(r, 1.0 / r), expected, 1e-13 * std::abs(kernel.gradient_factor(1e-6, 1e6)))
        << "r = " << r;
  }
  for (double r : {support, 1.2 * support, 3.0 * support}) EXPECT_EQ(kernel.gradient_factor(r, 1.0 / r), 0.0);
  EXPECT_TRUE(std::isfinite(kernel.gradient_factor(1e-300, 1e300)));
  EXPECT_LT(kernel.gradient_factor(1e-9, 1e9), 0.0);
}
