// The shapes of the smoothing kernels of physics/kernel.hpp as functions of r, written once for a
// double or a vector T (see core/lane_math.hpp and core/lanes-inl.hpp); the kernel's constants are
// doubles (N), or vectors made once outside the pair loop. Branch-free, so
// that a vector of pairs takes the piece each lane needs, and exactly 0 for r >= 2h: q is clamped at
// 2, so padding entries of a neighbour list placed outside the support contribute nothing.
//
// No include guard and no includes: this text is included inside a namespace, once for doubles
// (physics/kernel.hpp) and once per instruction set (physics/pair_loop-inl.hpp).

namespace shape {

// Cubic spline: W for 0 <= r.
template <int Dim, class N, class T>
T value_inside(const CubicSpline<Dim, N>& k, T r) {
  const T q = simd::min(r * k.inv_h, T(CubicSpline<Dim>::support));
  const T t = 2.0 - q;
  const T inner = 1.0 - 1.5 * q * q + 0.75 * q * q * q;
  const T outer = 0.25 * t * t * t;
  return k.norm * simd::select(q < 1.0, inner, outer);
}

// Cubic spline: dW/dr for 0 <= r (negative inside the support, zero at r = 0).
template <int Dim, class N, class T>
T derivative_inside(const CubicSpline<Dim, N>& k, T r) {
  const T q = simd::min(r * k.inv_h, T(CubicSpline<Dim>::support));
  const T t = 2.0 - q;
  const T inner = -3.0 * q + 2.25 * q * q;
  const T outer = -0.75 * t * t;
  return k.norm * k.inv_h * simd::select(q < 1.0, inner, outer);
}

// Cubic spline: the gradient factor F = dW/dr / r for 0 < r, given r and 1/r. On the inner piece
// q/r = 1/h, so only the outer piece needs 1/r.
template <int Dim, class N, class T>
T gradient_factor(const CubicSpline<Dim, N>& k, T r, T inv_r) {
  const T q = simd::min(r * k.inv_h, T(CubicSpline<Dim>::support));
  const T t = 2.0 - q;
  const T inner = k.norm * k.inv_h * k.inv_h * (-3.0 + 2.25 * q);
  const T outer = -0.75 * k.norm * k.inv_h * t * t * inv_r;
  return simd::select(q < 1.0, inner, outer);
}

// Wendland C2: W for 0 <= r.
template <int Dim, class N, class T>
T value_inside(const WendlandC2<Dim, N>& k, T r) {
  const T q = simd::min(r * k.inv_h, T(WendlandC2<Dim>::support));
  const T t = 1.0 - 0.5 * q;
  return k.norm * t * t * t * t * (2.0 * q + 1.0);
}

// Wendland C2: dW/dr for 0 <= r.
template <int Dim, class N, class T>
T derivative_inside(const WendlandC2<Dim, N>& k, T r) {
  const T q = simd::min(r * k.inv_h, T(WendlandC2<Dim>::support));
  const T t = 1.0 - 0.5 * q;
  return -5.0 * k.norm * k.inv_h * q * t * t * t;
}

// Wendland C2: F = dW/dr / r, where q/r = 1/h: no division.
template <int Dim, class N, class T>
T gradient_factor(const WendlandC2<Dim, N>& k, T r, T /*inv_r*/) {
  const T q = simd::min(r * k.inv_h, T(WendlandC2<Dim>::support));
  const T t = 1.0 - 0.5 * q;
  return -5.0 * k.norm * k.inv_h * k.inv_h * t * t * t;
}

}  // namespace shape
