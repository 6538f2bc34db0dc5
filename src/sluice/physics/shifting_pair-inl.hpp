// The sums particle shifting needs, as a pair interaction for the pair loop (physics/pair_loop-inl.hpp):
// over the neighbours j of i (fluid and wall particles alike, with the reference volume V = dx^Dim),
//   grad C_i   = sum_j V grad_i W_ij                                (the concentration gradient)
//   grad C^R_i = sum_j V (1 + R (W_ij / W(dx))^n) grad_i W_ij       (with Sun et al.'s (2017) anti-
//                                                                    clumping weight, R = 0.2, n = 4)
//   div r_i    = -sum_j V r_ij . grad_i W_ij                        (about Dim inside the water, less
//                                                                    where the support is cut by a
//                                                                    free surface)
// grad_i W_ij = F r_ij is opposite for j, r_ij . grad_i W_ij the same. physics/shifting.hpp turns them
// into the shift.
//
// No include guard and no includes: included inside a namespace that has `simd` and `shape` for T.

template <int Dim, class Kernel>
struct ShiftingPair {
  using Real = double;
  // The outputs, in the pair loop's order: grad C, grad C^R (opposite), div r (each side's own).
  static constexpr std::size_t kOpposite = 2 * Dim, kOwn = 1, kOutputs = kOpposite + kOwn;
  template <class T>
  struct Side {};
  template <class T>
  struct Rates {
    std::array<T, kOpposite> opposite;
    std::array<T, kOwn> to_i, to_j;
    T speed2, fluid_r2;  // unused (the pair loop's maxima)
  };

  Kernel kernel;
  double volume = 0.0;    // V = dx^Dim
  double tensile = 0.0;   // R
  double inv_w_dx = 0.0;  // 1 / W(dx)
  int exponent = 4;       // n
  double far_r2 = 0.0;

  template <class T, class Load>
  Side<T> side(Load&&) const {
    return {};
  }

  template <class T>
  Rates<T> operator()(const Side<T>&, const Side<T>&, const std::array<T, Dim>& r_ij) const {
    T r2 = r_ij[0] * r_ij[0];
    for (int d = 1; d < Dim; ++d) r2 = r2 + r_ij[d] * r_ij[d];
    const T r = simd::sqrt(r2);
    const T vf = volume * shape::gradient_factor(kernel, r, simd::inverse_root(r2, r));
    const T f = shape::value_inside(kernel, r) * inv_w_dx;
    T f_n = 1.0;
    for (int e = 0; e < exponent; ++e) f_n = f_n * f;
    const T weighted = vf * (1.0 + tensile * f_n);
    Rates<T> out;
    for (int d = 0; d < Dim; ++d) {
      out.opposite[d] = vf * r_ij[d];
      out.opposite[Dim + d] = weighted * r_ij[d];
    }
    out.to_i[0] = -(vf * r2);
    out.to_j[0] = out.to_i[0];
    out.speed2 = 0.0;
    out.fluid_r2 = far_r2;
    return out;
  }
};
