// SIMD lanes for the code compiled once per instruction set (physics/pair_loop-inl.hpp): `Pack` is
// the widest vector of doubles of the target Highway compiles for (2 lanes for SSE4 and the portable
// EMU128, 4 for AVX2, 8 for AVX-512), with the arithmetic operators and the same functions (min, max,
// select, quotient, sqrt) that core/lane_math.hpp gives doubles. The kernel and pair formulas are
// written once against these names (physics/kernel_shapes-inl.hpp, physics/pair_terms-inl.hpp) and
// compiled for doubles and for every target.
//
// A double converts to a Pack implicitly (a broadcast), so that `2.0 - q` and `m * F` read as they
// do for doubles.
//
// Included once per target by Highway's foreach_target (no include guard: a per-target toggle).
#if defined(SLUICE_CORE_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef SLUICE_CORE_LANES_INL_H_
#undef SLUICE_CORE_LANES_INL_H_
#else
#define SLUICE_CORE_LANES_INL_H_
#endif

#include <cstddef>

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE::simd {

namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<double>;

struct Mask {
  hn::Mask<D> m;
};

struct Pack {
  hn::Vec<D> v;
  Pack() = default;
  Pack(hn::Vec<D> x) : v(x) {}         // NOLINT(google-explicit-constructor)
  Pack(double x) : v(hn::Set(D(), x)) {}  // NOLINT(google-explicit-constructor): broadcast
};

HWY_API std::size_t lanes() { return hn::Lanes(D()); }

HWY_API Pack operator+(Pack a, Pack b) { return hn::Add(a.v, b.v); }
HWY_API Pack operator-(Pack a, Pack b) { return hn::Sub(a.v, b.v); }
HWY_API Pack operator*(Pack a, Pack b) { return hn::Mul(a.v, b.v); }
HWY_API Pack operator-(Pack a) { return hn::Neg(a.v); }
HWY_API Pack& operator+=(Pack& a, Pack b) { return a = a + b; }
HWY_API Mask operator<(Pack a, Pack b) { return {hn::Lt(a.v, b.v)}; }
HWY_API Mask operator>(Pack a, Pack b) { return {hn::Gt(a.v, b.v)}; }
HWY_API Mask operator!=(Pack a, Pack b) { return {hn::Ne(a.v, b.v)}; }
HWY_API Mask operator&(Mask a, Mask b) { return {hn::And(a.m, b.m)}; }

HWY_API Pack min(Pack a, Pack b) { return hn::Min(a.v, b.v); }
HWY_API Pack max(Pack a, Pack b) { return hn::Max(a.v, b.v); }
HWY_API Pack select(Mask c, Pack a, Pack b) { return hn::IfThenElse(c.m, a.v, b.v); }
HWY_API Pack quotient(Pack a, Pack b) { return hn::Div(a.v, b.v); }
HWY_API Pack sqrt(Pack x) { return hn::Sqrt(x.v); }

HWY_API double reduce_add(Pack a) { return hn::GetLane(hn::SumOfLanes(D(), a.v)); }
HWY_API double reduce_max(Pack a) { return hn::GetLane(hn::MaxOfLanes(D(), a.v)); }
HWY_API double reduce_min(Pack a) { return hn::GetLane(hn::MinOfLanes(D(), a.v)); }

HWY_API Pack load(const double* p) { return hn::LoadU(D(), p); }
HWY_API void store(Pack a, double* p) { hn::StoreU(a.v, D(), p); }
// base[j], ..., base[j + n - 1] (n <= lanes()), `fill` in the other lanes, from an array of `size`
// values: a whole-vector load where the vector lies inside the array (the lanes past n are replaced),
// otherwise, at the array's end, through a buffer. (Not Highway's MaskedLoad, which on SSE4 reads the
// whole vector and which GCC 12 compiled on AVX2 for a known n into stores and a reload of the
// stack: a stall of every partial vector.)
HWY_API Pack load_within(const double* base, std::size_t j, std::size_t n, std::size_t size, double fill) {
  const D d;
  if (j + hn::Lanes(d) <= size) {
    const auto v = hn::LoadU(d, base + j);
    return n == hn::Lanes(d) ? v : hn::IfThenElse(hn::FirstN(d, n), v, hn::Set(d, fill));
  }
  HWY_ALIGN double buffer[hn::MaxLanes(D())];
  for (std::size_t k = 0; k < hn::Lanes(d); ++k) buffer[k] = k < n ? base[j + k] : fill;
  return hn::Load(d, buffer);
}
// The whole vector base[j], ... from an array of `size` values; lanes past its end are 0.
HWY_API Pack load_at(const double* base, std::size_t j, std::size_t size) {
  const D d;
  if (j + hn::Lanes(d) <= size) return hn::LoadU(d, base + j);
  HWY_ALIGN double buffer[hn::MaxLanes(D())];
  for (std::size_t k = 0; k < hn::Lanes(d); ++k) buffer[k] = j + k < size ? base[j + k] : 0.0;
  return hn::Load(d, buffer);
}

}  // namespace sluice::HWY_NAMESPACE::simd
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
