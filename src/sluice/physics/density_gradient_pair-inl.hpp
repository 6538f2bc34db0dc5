// The sums of the renormalised density gradient (physics/density_gradient.hpp) as a pair interaction
// for the pair loop (physics/pair_loop-inl.hpp): over the fluid neighbours j of a fluid particle i,
// with V_j = m / rho_j and grad_i W_ij = F r_ij,
//   M_i = sum_j V_j r_ji (x) grad_i W_ij = -sum_j V_j F r_ij r_ij^T   (symmetric: its upper triangle,
//                                                                      row by row)
//   g_i = sum_j V_j (rho_j - rho_i) grad_i W_ij = sum_j V_j (rho_j - rho_i) F r_ij.
// Particle j's terms of the pair are the same with V_i for V_j (r_ji and grad_j W_ji both change sign,
// and so does rho_i - rho_j), so all of them are "own" outputs. Pairs with a wall particle give nothing.
//
// No include guard and no includes: included inside a namespace that has `simd` and `shape` for T.

template <int Dim, class Kernel>
struct DensityGradientPair {
  using Real = double;
  static constexpr std::size_t kMatrix = Dim * (Dim + 1) / 2;
  static constexpr std::size_t kOpposite = 0, kOwn = kMatrix + Dim, kOutputs = kOpposite + kOwn;
  template <class T>
  struct Side {
    T rho, volume, fluid;
  };
  template <class T>
  struct Rates {
    std::array<T, kOpposite> opposite;
    std::array<T, kOwn> to_i, to_j;
    T speed2, fluid_r2;  // unused (the pair loop's maxima)
  };

  Kernel kernel;
  double mass = 0.0;
  double far_r2 = 0.0;
  const double* rho = nullptr;
  const double* fluid = nullptr;

  template <class T, class Load>
  Side<T> side(Load&& load) const {
    const T rho_side = load(rho);
    return {rho_side, simd::quotient(T(mass), rho_side), load(fluid)};
  }

  template <class T>
  Rates<T> operator()(const Side<T>& i, const Side<T>& j, const std::array<T, Dim>& r_ij) const {
    T r2 = r_ij[0] * r_ij[0];
    for (int d = 1; d < Dim; ++d) r2 = r2 + r_ij[d] * r_ij[d];
    const T r = simd::sqrt(r2);
    const T F = i.fluid * j.fluid * shape::gradient_factor(kernel, r, simd::inverse_root(r2, r));
    Rates<T> out;
    std::size_t k = 0;
    for (int a = 0; a < Dim; ++a)
      for (int b = a; b < Dim; ++b) {
        const T m_ab = -(F * r_ij[a] * r_ij[b]);
        out.to_i[k] = j.volume * m_ab;
        out.to_j[k] = i.volume * m_ab;
        ++k;
      }
    const T f_drho = F * (j.rho - i.rho);
    for (int d = 0; d < Dim; ++d) {
      const T g_d = f_drho * r_ij[d];
      out.to_i[kMatrix + d] = j.volume * g_d;
      out.to_j[kMatrix + d] = i.volume * g_d;
    }
    out.speed2 = 0.0;
    out.fluid_r2 = far_r2;
    return out;
  }
};
