// Smoothing kernels W(r, h) with analytic derivatives dW/dr; support radius 2h. A kernel object holds
// its constants; its shape as a function of r is in physics/kernel_shapes-inl.hpp, written once for
// doubles (the member functions here) and for the vector lanes of the pair loop.
#pragma once

#include <numbers>
#include <variant>

#include "sluice/core/lane_math.hpp"

namespace sluice {

// Cubic spline (Monaghan & Lattanzio 1985), normalised in 1, 2 or 3 dimensions.
// Num is double, or in the pair loop a vector of constants (as<T>(): made once, outside the loop).
template <int Dim, class Num = double>
struct CubicSpline {
  static constexpr double support = 2.0;  // in units of h

  Num h;
  Num inv_h;
  Num norm;  // sigma / h^Dim

  CubicSpline(const Num& h_, const Num& inv_h_, const Num& norm_) : h(h_), inv_h(inv_h_), norm(norm_) {}
  template <class T>
  [[nodiscard]] CubicSpline<Dim, T> as() const {
    return {T(h), T(inv_h), T(norm)};
  }

  explicit CubicSpline(double smoothing_length) : h(smoothing_length), inv_h(1.0 / smoothing_length) {
    static_assert(Dim >= 1 && Dim <= 3);
    if constexpr (Dim == 1) norm = 2.0 / (3.0 * h);
    if constexpr (Dim == 2) norm = 10.0 / (7.0 * std::numbers::pi * h * h);
    if constexpr (Dim == 3) norm = 1.0 / (std::numbers::pi * h * h * h);
  }

  [[nodiscard]] double value(double r) const { return r < support * h ? value_inside(r) : 0.0; }
  // W for 0 <= r, exactly 0 for r >= 2h, without a branch on r.
  [[nodiscard]] double value_inside(double r) const;
  // dW/dr (negative inside the support, zero outside and at r = 0).
  [[nodiscard]] double derivative(double r) const { return r < support * h ? derivative_inside(r) : 0.0; }
  [[nodiscard]] double derivative_inside(double r) const;
  // F = dW/dr / r for 0 < r (exactly 0 for r >= 2h), given r and 1/r.
  [[nodiscard]] double gradient_factor(double r, double inv_r) const;
};

// Wendland C2 (Wendland 1995), in the q in [0, 2] form used by DualSPHysics; 2D and 3D only.
// Num is double, or in the pair loop a vector of constants (as<T>(): made once, outside the loop).
template <int Dim, class Num = double>
struct WendlandC2 {
  static constexpr double support = 2.0;

  Num h;
  Num inv_h;
  Num norm;

  WendlandC2(const Num& h_, const Num& inv_h_, const Num& norm_) : h(h_), inv_h(inv_h_), norm(norm_) {}
  template <class T>
  [[nodiscard]] WendlandC2<Dim, T> as() const {
    return {T(h), T(inv_h), T(norm)};
  }

  explicit WendlandC2(double smoothing_length) : h(smoothing_length), inv_h(1.0 / smoothing_length) {
    static_assert(Dim == 2 || Dim == 3);
    if constexpr (Dim == 2) norm = 7.0 / (4.0 * std::numbers::pi * h * h);
    if constexpr (Dim == 3) norm = 21.0 / (16.0 * std::numbers::pi * h * h * h);
  }

  [[nodiscard]] double value(double r) const { return r < support * h ? value_inside(r) : 0.0; }
  [[nodiscard]] double value_inside(double r) const;
  [[nodiscard]] double derivative(double r) const { return r < support * h ? derivative_inside(r) : 0.0; }
  [[nodiscard]] double derivative_inside(double r) const;
  [[nodiscard]] double gradient_factor(double r, double inv_r) const;
};

#include "sluice/physics/kernel_shapes-inl.hpp"

template <int Dim, class Num>
double CubicSpline<Dim, Num>::value_inside(double r) const { return shape::value_inside(*this, r); }
template <int Dim, class Num>
double CubicSpline<Dim, Num>::derivative_inside(double r) const { return shape::derivative_inside(*this, r); }
template <int Dim, class Num>
double CubicSpline<Dim, Num>::gradient_factor(double r, double inv_r) const { return shape::gradient_factor(*this, r, inv_r); }
template <int Dim, class Num>
double WendlandC2<Dim, Num>::value_inside(double r) const { return shape::value_inside(*this, r); }
template <int Dim, class Num>
double WendlandC2<Dim, Num>::derivative_inside(double r) const { return shape::derivative_inside(*this, r); }
template <int Dim, class Num>
double WendlandC2<Dim, Num>::gradient_factor(double r, double inv_r) const { return shape::gradient_factor(*this, r, inv_r); }

// The kernels a run can use; the index of the alternative selects the compiled pair loop.
template <int Dim>
using AnyKernel = std::variant<CubicSpline<Dim>, WendlandC2<Dim>>;

}  // namespace sluice
