// Eight doubles in an AVX-512 register, with just the operations the pair loop needs, so that the
// pair terms (physics/pair_terms.hpp) and kernels (physics/kernel.hpp) are written once, as templates,
// and evaluated on a double or on eight pairs at a time. The scalar overloads of min, max, select,
// quotient and inverse_sqrt are here too, so that the same template reads the same for both.
//
// On eight lanes, quotient and inverse_sqrt avoid the divider: a 14-bit hardware estimate (vrcp14pd,
// vrsqrt14pd) refined by two Newton steps is accurate to a few units in the last place, where vdivpd
// and vsqrtpd each occupy the divider for 16 or more cycles per vector, and the pair loop has three.
#pragma once

#include <algorithm>
#include <cmath>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SLUICE_HAVE_AVX512 1
#endif

namespace sluice::simd {

inline double min(double a, double b) { return std::min(a, b); }
inline double max(double a, double b) { return std::max(a, b); }
inline double select(bool c, double a, double b) { return c ? a : b; }
inline double quotient(double a, double b) { return a / b; }
inline double inverse_sqrt(double x) { return 1.0 / std::sqrt(x); }
inline double sqrt(double x) { return std::sqrt(x); }

#if defined(SLUICE_HAVE_AVX512)

struct Mask8 {
  __mmask8 m;
};

struct V8 {
  __m512d v;
  V8() = default;
  V8(__m512d x) : v(x) {}                          // NOLINT(google-explicit-constructor)
  V8(double x) : v(_mm512_set1_pd(x)) {}           // NOLINT(google-explicit-constructor): broadcast
  static V8 load(const double* p) { return _mm512_loadu_pd(p); }
  // Lanes outside `m` are `fill`.
  static V8 load(Mask8 m, const double* p, double fill) { return _mm512_mask_loadu_pd(_mm512_set1_pd(fill), m.m, p); }
  // base[index[k]] for the lanes in m, 0 elsewhere.
  static V8 gather(Mask8 m, __m256i index, const double* base) {
    return _mm512_mask_i32gather_pd(_mm512_setzero_pd(), m.m, index, base, 8);
  }
  void scatter(Mask8 m, __m256i index, double* base) const { _mm512_mask_i32scatter_pd(base, m.m, index, v, 8); }
};

inline V8 operator+(V8 a, V8 b) { return _mm512_add_pd(a.v, b.v); }
inline V8 operator-(V8 a, V8 b) { return _mm512_sub_pd(a.v, b.v); }
inline V8 operator*(V8 a, V8 b) { return _mm512_mul_pd(a.v, b.v); }
inline V8 operator-(V8 a) { return _mm512_sub_pd(_mm512_setzero_pd(), a.v); }
inline V8& operator+=(V8& a, V8 b) { return a = a + b; }
inline Mask8 operator<(V8 a, V8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
inline Mask8 operator!=(V8 a, V8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_NEQ_UQ)}; }
// The maskz_ forms with all lanes set: GCC 12's unmasked forms pass an undefined vector that
// -Wuninitialized reports.
inline constexpr __mmask8 all8 = 0xFF;
inline V8 min(V8 a, V8 b) { return _mm512_maskz_min_pd(all8, a.v, b.v); }
inline V8 max(V8 a, V8 b) { return _mm512_maskz_max_pd(all8, a.v, b.v); }
inline V8 select(Mask8 c, V8 a, V8 b) { return _mm512_mask_blend_pd(c.m, b.v, a.v); }

// 1/b: vrcp14pd (relative error < 2^-14), then two Newton steps y <- y (2 - b y): < 2^-52 plus rounding.
inline V8 reciprocal(V8 b) {
  __m512d y = _mm512_maskz_rcp14_pd(all8, b.v);
  const __m512d two = _mm512_set1_pd(2.0);
  y = _mm512_mul_pd(y, _mm512_fnmadd_pd(b.v, y, two));
  y = _mm512_mul_pd(y, _mm512_fnmadd_pd(b.v, y, two));
  return y;
}
inline V8 quotient(V8 a, V8 b) { return a * reciprocal(b); }
inline V8 sqrt(V8 x) { return _mm512_maskz_sqrt_pd(all8, x.v); }

// 1/sqrt(x) for x > 0: vrsqrt14pd, then two Newton steps y <- y (3 - x y^2) / 2.
inline V8 inverse_sqrt(V8 x) {
  __m512d y = _mm512_maskz_rsqrt14_pd(all8, x.v);
  const __m512d half = _mm512_set1_pd(0.5), three = _mm512_set1_pd(3.0);
  for (int step = 0; step < 2; ++step) {
    const __m512d xy2 = _mm512_mul_pd(_mm512_mul_pd(x.v, y), y);
    y = _mm512_mul_pd(_mm512_mul_pd(half, y), _mm512_sub_pd(three, xy2));
  }
  return y;
}

// Horizontal reductions, halving the vector three times.
#define SLUICE_SIMD_REDUCE(name, op)                                                                      \
  inline double name(V8 a) {                                                                              \
    const __m256d quad = _mm256_##op##_pd(_mm512_maskz_extractf64x4_pd(0xF, a.v, 0), _mm512_maskz_extractf64x4_pd(0xF, a.v, 1)); \
    const __m128d pair = _mm_##op##_pd(_mm256_castpd256_pd128(quad), _mm256_extractf128_pd(quad, 1));    \
    return _mm_cvtsd_f64(_mm_##op##_sd(pair, _mm_unpackhi_pd(pair, pair)));                              \
  }
SLUICE_SIMD_REDUCE(reduce_add, add)
SLUICE_SIMD_REDUCE(reduce_max, max)
SLUICE_SIMD_REDUCE(reduce_min, min)
#undef SLUICE_SIMD_REDUCE

#endif

}  // namespace sluice::simd
