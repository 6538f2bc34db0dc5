// The few functions the kernel and pair formulas use besides arithmetic, for doubles. The formulas
// (physics/kernel_shapes-inl.hpp, physics/pair_terms-inl.hpp) are written once against these names;
// core/lanes-inl.hpp gives the same names for the SIMD vectors of each instruction set, so that the
// same text is compiled for one pair or for a vector of pairs.
#pragma once

#include <algorithm>
#include <cmath>

namespace sluice::simd {

inline double min(double a, double b) { return std::min(a, b); }
inline double max(double a, double b) { return std::max(a, b); }
inline double select(bool c, double a, double b) { return c ? a : b; }
inline double quotient(double a, double b) { return a / b; }
inline double sqrt(double x) { return std::sqrt(x); }
// 1/r for r = sqrt(r2), given both (the vectors of floats compute it from r2 alone).
inline double inverse_root(double /*r2*/, double r) { return 1.0 / r; }

}  // namespace sluice::simd
