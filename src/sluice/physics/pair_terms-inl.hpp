// The WCSPH equations as small functions of a particle pair (i, j). Notation follows docs/physics.md:
// r_ij = x_i - x_j, r = |r_ij|, e_ij = r_ij / r, v_ij = v_i - v_j, dW = dW/dr(r) (negative), m = m_j.
// They take the kernel's gradient factor F = dW/dr / r (so grad_i W_ij = F r_ij; see kernel.hpp,
// gradient_factor), which removes the 1/r of every term: the momentum terms return factors of r_ij
// or v_ij, the density terms scalars.
// Each is a template on the number type T: a double for one pair (physics/pair_terms.hpp), or a
// vector of pairs (simd::Lanes of core/lanes-inl.hpp, in the code compiled per instruction set).
// The constants of the run (C) are doubles, or vectors made once outside the pair loop.
//
// No include guard and no includes: this text is included inside a namespace, once for doubles and
// once per instruction set, where `simd::` names that namespace's functions of core/lane_math.hpp or
// core/lanes-inl.hpp.

namespace pair {

// Momentum, pressure part: a_i += -m (P_i/rho_i^2 + P_j/rho_j^2) dW e_ij.  Returns the factor of r_ij.
template <class T, class C>
T pressure(C m, T p_over_rho2_i, T p_over_rho2_j, T F) {
  return -m * (p_over_rho2_i + p_over_rho2_j) * F;
}

// Momentum, viscous part (docs/physics.md, "Momentum"): a_i += mu m (1/rho_i^2 + 1/rho_j^2) dW v_ij / r.
// Returns the factor of v_ij.
template <class T, class C>
T laminar_viscosity(C mu, C m, T inv_rho2_i, T inv_rho2_j, T F) {
  return mu * m * (inv_rho2_i + inv_rho2_j) * F;
}

// Monaghan (1992) artificial viscosity: a_i += -m Pi_ij dW e_ij with
// Pi_ij = -alpha c0 mu_ij / rho_mean, mu_ij = h (v_ij . r_ij) / (r^2 + 0.01 h^2), only for approaching pairs.
// Returns the factor of r_ij.
template <class T, class C>
T artificial_viscosity(T alpha, C c0, C h, C m, T v_dot_r, T r2, T rho_mean, T F) {
  // Pi_ij with one division (the pair loop's costliest operations are its divisions).
  const T pi_ij = simd::quotient(-alpha * c0 * h * simd::min(v_dot_r, T(0.0)), (r2 + 0.01 * h * h) * rho_mean);
  return -m * pi_ij * F;
}

// Monaghan (2000) artificial pressure against the tensile instability: a_i += -m R_ij f^n dW e_ij,
// f = W(r)/W(dx), R_ij = R_i + R_j with R = eps |P|/rho^2 for particles under tension (P < 0) and
// R = 0.01 P/rho^2 otherwise (Monaghan's small positive-pressure term, which stops pairing).
// Returns the factor of r_ij; f_n = f^n.
template <class T, class C>
T artificial_pressure(C m, T r_i, T r_j, T f_n, T F) {
  return -m * (r_i + r_j) * f_n * F;
}

// Continuity: drho_i/dt += m dW (v_ij . e_ij) = m F (v_ij . r_ij).
template <class T, class C>
T continuity(C m, T F, T v_dot_r) {
  return m * F * v_dot_r;
}

// delta-SPH density diffusion (Molteni & Colagrossi 2009) with the density difference a gradient
// explains removed, so that diffusion does not flatten the hydrostatic profile: drho_hydro_ij is
// rho_j - rho_i of the hydrostatic gradient (Fourtakas et al. 2019) or of the two particles' mean
// renormalised gradient (Antuono et al. 2010: physics/density_gradient.hpp),
// drho_i/dt += delta h c0 * 2 (rho_j - rho_i - drho_hydro_ij) (r_ji . grad_i W) / r^2 * m / rho_j,
// and r_ji . grad_i W / r^2 = -F. This returns the flux D = -2 delta h c0 m F (rho_j - rho_i -
// drho_hydro_ij): particle i gains D / rho_j and particle j gains -D / rho_i (the same formula with
// i and j swapped).
template <class T, class C>
T density_diffusion_flux(C delta_h_c0, C m, T rho_i, T rho_j, T drho_hydro_ij, T F) {
  return -2.0 * delta_h_c0 * m * F * (rho_j - rho_i - drho_hydro_ij);
}

}  // namespace pair
