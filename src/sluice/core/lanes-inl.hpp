// SIMD lanes for the code compiled once per instruction set (physics/pair_loop-inl.hpp): `Lanes<R>`
// is the widest vector of R (double or float) of the target Highway compiles for (for doubles: 2
// lanes for SSE4 and the portable EMU128, 4 for AVX2, 8 for AVX-512; twice as many floats), with the
// arithmetic operators and the same functions (min, max, select, quotient, sqrt) that
// core/lane_math.hpp gives doubles. The kernel and pair formulas are written once against these names
// (physics/kernel_shapes-inl.hpp, physics/pair_terms-inl.hpp) and compiled for doubles and for every
// target, in double and in single precision. `Pack` is the vector of doubles.
//
// A double converts to a vector implicitly (a broadcast, rounded to R), so that `2.0 - q` and `m * F`
// read as they do for doubles: the operators are the vector's own (hidden friends), which take the
// conversion; in the functions, the second operand converts.
//
// Included once per target by Highway's foreach_target (no include guard: a per-target toggle).
#if defined(SLUICE_CORE_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SLUICE_CORE_LANES_INL_H_
#undef SLUICE_CORE_LANES_INL_H_
#else
#define SLUICE_CORE_LANES_INL_H_
#endif

#include <cstddef>
#include <type_traits>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE::simd {

namespace hn = hwy::HWY_NAMESPACE;

template <class R>
using Tag = hn::ScalableTag<R>;
using D = Tag<double>;

template <class R>
struct MaskOf {
  hn::Mask<Tag<R>> m;
  friend HWY_INLINE HWY_ATTR MaskOf operator&(MaskOf a, MaskOf b) { return {hn::And(a.m, b.m)}; }
};

template <class R>
struct Lanes {
  using Real = R;
  hn::Vec<Tag<R>> v;
  Lanes() = default;
  Lanes(hn::Vec<Tag<R>> x) : v(x) {}                              // NOLINT(google-explicit-constructor)
  Lanes(double x) : v(hn::Set(Tag<R>(), static_cast<R>(x))) {}  // NOLINT(google-explicit-constructor): broadcast

  friend HWY_INLINE HWY_ATTR Lanes operator+(Lanes a, Lanes b) { return hn::Add(a.v, b.v); }
  friend HWY_INLINE HWY_ATTR Lanes operator-(Lanes a, Lanes b) { return hn::Sub(a.v, b.v); }
  friend HWY_INLINE HWY_ATTR Lanes operator*(Lanes a, Lanes b) { return hn::Mul(a.v, b.v); }
  friend HWY_INLINE HWY_ATTR Lanes operator-(Lanes a) { return hn::Neg(a.v); }
  friend HWY_INLINE HWY_ATTR Lanes& operator+=(Lanes& a, Lanes b) { return a = a + b; }
  friend HWY_INLINE HWY_ATTR MaskOf<R> operator<(Lanes a, Lanes b) { return {hn::Lt(a.v, b.v)}; }
  friend HWY_INLINE HWY_ATTR MaskOf<R> operator>(Lanes a, Lanes b) { return {hn::Gt(a.v, b.v)}; }
  friend HWY_INLINE HWY_ATTR MaskOf<R> operator!=(Lanes a, Lanes b) { return {hn::Ne(a.v, b.v)}; }
};

using Pack = Lanes<double>;
using Mask = MaskOf<double>;

template <class R = double>
HWY_API std::size_t lanes() {
  return hn::Lanes(Tag<R>());
}

// The second operand of these is not deduced: a double there converts, as for the operators.
template <class R>
HWY_API Lanes<R> min(Lanes<R> a, std::type_identity_t<Lanes<R>> b) {
  return hn::Min(a.v, b.v);
}
template <class R>
HWY_API Lanes<R> max(Lanes<R> a, std::type_identity_t<Lanes<R>> b) {
  return hn::Max(a.v, b.v);
}
template <class R>
HWY_API Lanes<R> select(MaskOf<R> c, Lanes<R> a, std::type_identity_t<Lanes<R>> b) {
  return hn::IfThenElse(c.m, a.v, b.v);
}
template <class R>
HWY_API Lanes<R> quotient(Lanes<R> a, std::type_identity_t<Lanes<R>> b) {
  return hn::Div(a.v, b.v);
}
template <class R>
HWY_API Lanes<R> sqrt(Lanes<R> x) {
  return hn::Sqrt(x.v);
}

// x, with the compiler made to forget where it came from. A constant made by a broadcast stays a
// vector: GCC otherwise turns the products of broadcasts into scalar products broadcast again, and
// redoes them on every pass of the pair loop instead of reloading the vector.
template <class R>
HWY_API Lanes<R> opaque(Lanes<R> x) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128
  asm("" : "+v"(x.v.raw));
#endif
  return x;
}

// 1/r for r = sqrt(r2), given both: 1/r for doubles; for floats from r2 alone (below).
template <class R>
HWY_API Lanes<R> inverse_root(Lanes<R> /*r2*/, Lanes<R> r) {
  return hn::Div(hn::Set(Tag<R>(), R(1)), r.v);
}

// For floats on x86 (SSE4, AVX2, AVX-512), the instruction set's approximate 1/sqrt(x) and 1/x (to
// 12 or 14 bits) with one Newton step (to about 2 ulp), in place of the divisions and square roots:
// sqrt(x) = x / sqrt(x) (0 at x = 0), a / b = a (1/b). Elsewhere (the portable targets, whose estimates
// are coarser, and NEON's 8 bits) the exact operations.
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
HWY_API Lanes<float> inverse_sqrt(Lanes<float> x) {
  const Tag<float> d;
  const auto y = hn::ApproximateReciprocalSqrt(x.v);
  // y (3 - x y^2) / 2
  return hn::Mul(hn::Mul(hn::Set(d, 0.5f), y), hn::NegMulAdd(hn::Mul(x.v, y), y, hn::Set(d, 3.0f)));
}
HWY_API Lanes<float> sqrt(Lanes<float> x) {
  const Tag<float> d;
  return hn::Mul(x.v, inverse_sqrt(hn::Max(x.v, hn::Set(d, 1e-30f))).v);
}
HWY_API Lanes<float> inverse_root(Lanes<float> r2, Lanes<float> /*r*/) {
  return inverse_sqrt(hn::Max(r2.v, hn::Set(Tag<float>(), 1e-30f)));
}
HWY_API Lanes<float> quotient(Lanes<float> a, Lanes<float> b) {
  const Tag<float> d;
  const auto y = hn::ApproximateReciprocal(b.v);
  // y (2 - b y)
  return hn::Mul(a.v, hn::Mul(y, hn::NegMulAdd(b.v, y, hn::Set(d, 2.0f))));
}
#endif

// The sums and extremes of the lanes, as doubles.
template <class R>
HWY_API double reduce_add(Lanes<R> a) {
  return static_cast<double>(hn::GetLane(hn::SumOfLanes(Tag<R>(), a.v)));
}
template <class R>
HWY_API double reduce_max(Lanes<R> a) {
  return static_cast<double>(hn::GetLane(hn::MaxOfLanes(Tag<R>(), a.v)));
}
template <class R>
HWY_API double reduce_min(Lanes<R> a) {
  return static_cast<double>(hn::GetLane(hn::MinOfLanes(Tag<R>(), a.v)));
}

template <class R>
HWY_API Lanes<R> load(const R* p) {
  return hn::LoadU(Tag<R>(), p);
}
template <class R>
HWY_API void store(Lanes<R> a, R* p) {
  hn::StoreU(a.v, Tag<R>(), p);
}
// base[j], ..., base[j + n - 1] (n <= lanes()), `fill` in the other lanes, from an array of `size`
// values: a whole-vector load where the vector lies inside the array (the lanes past n are replaced),
// otherwise, at the array's end, through a buffer. (Not Highway's MaskedLoad, which on SSE4 reads the
// whole vector and which GCC 12 compiled on AVX2 for a known n into stores and a reload of the
// stack: a stall of every partial vector.)
template <class R>
HWY_API Lanes<R> load_within(const R* base, std::size_t j, std::size_t n, std::size_t size, R fill) {
  const Tag<R> d;
  if (j + hn::Lanes(d) <= size) {
    const auto v = hn::LoadU(d, base + j);
    return n == hn::Lanes(d) ? v : hn::IfThenElse(hn::FirstN(d, n), v, hn::Set(d, fill));
  }
  HWY_ALIGN R buffer[hn::MaxLanes(Tag<R>())];
  for (std::size_t k = 0; k < hn::Lanes(d); ++k) buffer[k] = k < n ? base[j + k] : fill;
  return hn::Load(d, buffer);
}
// The whole vector base[j], ... from an array of `size` values; lanes past its end are 0.
template <class R>
HWY_API Lanes<R> load_at(const R* base, std::size_t j, std::size_t size) {
  const Tag<R> d;
  if (j + hn::Lanes(d) <= size) return hn::LoadU(d, base + j);
  HWY_ALIGN R buffer[hn::MaxLanes(Tag<R>())];
  for (std::size_t k = 0; k < hn::Lanes(d); ++k) buffer[k] = j + k < size ? base[j + k] : R(0);
  return hn::Load(d, buffer);
}

}  // namespace sluice::HWY_NAMESPACE::simd
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
