// Smoothing kernels W(r, h) with analytic derivatives dW/dr; support radius 2h.
#pragma once

#include <algorithm>
#include <numbers>

#include "sluice/core/simd.hpp"

namespace sluice {

// Cubic spline (Monaghan & Lattanzio 1985), normalised in 1, 2 or 3 dimensions.
template <int Dim>
struct CubicSpline {
  static constexpr double support = 2.0;  // in units of h

  double h;
  double inv_h;
  double norm;  // sigma / h^Dim

  explicit CubicSpline(double smoothing_length) : h(smoothing_length), inv_h(1.0 / smoothing_length) {
    static_assert(Dim >= 1 && Dim <= 3);
    if constexpr (Dim == 1) norm = 2.0 / (3.0 * h);
    if constexpr (Dim == 2) norm = 10.0 / (7.0 * std::numbers::pi * h * h);
    if constexpr (Dim == 3) norm = 1.0 / (std::numbers::pi * h * h * h);
  }

  [[nodiscard]] double value(double r) const { return r < support * h ? value_inside(r) : 0.0; }

  // W for 0 <= r < 2h, branch-free; exactly 0 for r >= 2h (q is clamped at 2, so padding entries of
  // a neighbour list placed outside the support contribute nothing). T is double or simd::V8.
  template <class T>
  [[nodiscard]] T value_inside(T r) const {
    const T q = simd::min(r * inv_h, T(support));  // beyond the support: exactly 0
    const T t = 2.0 - q;
    const T inner = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
    const T outer = 0.25 * t * t * t;
    return norm * simd::select(q < 1.0, inner, outer);
  }

  // dW/dr (negative inside the support, zero outside and at r = 0).
  [[nodiscard]] double derivative(double r) const { return r < support * h ? derivative_inside(r) : 0.0; }

  // dW/dr for 0 <= r < 2h, without branches so that the pair loop vectorises; exactly 0 for r >= 2h.
  template <class T>
  [[nodiscard]] T derivative_inside(T r) const {
    const T q = simd::min(r * inv_h, T(support));  // beyond the support: exactly 0
    const T t = 2.0 - q;
    const T inner = -3.0 * q + 2.25 * q * q;
    const T outer = -0.75 * t * t;
    return norm * inv_h * simd::select(q < 1.0, inner, outer);
  }

  // The gradient factor F = dW/dr / r for 0 < r (exactly 0 for r >= 2h), given r and 1/r: on the
  // inner piece q/r = 1/h, so only the outer piece needs 1/r.
  template <class T>
  [[nodiscard]] T gradient_factor(T r, T inv_r) const {
    const T q = simd::min(r * inv_h, T(support));
    const T t = 2.0 - q;
    const T inner = norm * inv_h * inv_h * (-3.0 + 2.25 * q);
    const T outer = -0.75 * norm * inv_h * t * t * inv_r;
    return simd::select(q < 1.0, inner, outer);
  }
};

// Wendland C2 (Wendland 1995), in the q in [0, 2] form used by DualSPHysics; 2D and 3D only.
template <int Dim>
struct WendlandC2 {
  static constexpr double support = 2.0;

  double h;
  double inv_h;
  double norm;

  explicit WendlandC2(double smoothing_length) : h(smoothing_length), inv_h(1.0 / smoothing_length) {
    static_assert(Dim == 2 || Dim == 3);
    if constexpr (Dim == 2) norm = 7.0 / (4.0 * std::numbers::pi * h * h);
    if constexpr (Dim == 3) norm = 21.0 / (16.0 * std::numbers::pi * h * h * h);
  }

  [[nodiscard]] double value(double r) const { return r < support * h ? value_inside(r) : 0.0; }

  template <class T>
  [[nodiscard]] T value_inside(T r) const {
    const T q = simd::min(r * inv_h, T(support));  // beyond the support: exactly 0
    const T t = 1.0 - 0.5 * q;
    return norm * t * t * t * t * (2.0 * q + 1.0);
  }

  [[nodiscard]] double derivative(double r) const { return r < support * h ? derivative_inside(r) : 0.0; }

  template <class T>
  [[nodiscard]] T derivative_inside(T r) const {
    const T q = simd::min(r * inv_h, T(support));  // beyond the support: exactly 0
    const T t = 1.0 - 0.5 * q;
    return -5.0 * norm * inv_h * q * t * t * t;
  }

  // F = dW/dr / r (exactly 0 for r >= 2h): q/r = 1/h, so no division.
  template <class T>
  [[nodiscard]] T gradient_factor(T r, T /*inv_r*/) const {
    const T q = simd::min(r * inv_h, T(support));
    const T t = 1.0 - 0.5 * q;
    return -5.0 * norm * inv_h * inv_h * t * t * t;
  }
};

}  // namespace sluice
