// The renormalised density gradient of the full delta-SPH (Antuono et al. 2010, Comput. Phys. Commun.
// 181:532; Marrone et al. 2011, Comput. Methods Appl. Mech. Engrg. 200:1526): at each fluid particle,
//   <grad rho>_i = L_i sum_j (rho_j - rho_i) grad_i W_ij V_j,   L_i = [sum_j r_ji (x) grad_i W_ij V_j]^-1,
// over the fluid neighbours j (V_j = m / rho_j). The renormalisation L_i makes it exact for a linear
// density field even where the support is cut by a wall or the free surface. Density diffusion then
// diffuses only what is left of rho_j - rho_i beyond the mean of the two particles' gradients
// (physics/wcsph_pair-inl.hpp): the full delta-SPH term
//   D_i = delta h c0 sum_j psi_ij . grad_i W_ij V_j,
//   psi_ij = 2 (rho_j - rho_i) r_ji / |r_ij|^2 - (<grad rho>_i + <grad rho>_j),
// instead of the hydrostatic part alone (Fourtakas et al. 2019, the default).
//
// Where the matrix is near singular (a particle with few neighbours, or all of them in a line: spray,
// a thin jet), the gradient is 0 there: the plain Molteni & Colagrossi term.
#pragma once

#include <array>
#include <cmath>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/rates.hpp"

namespace sluice {

// A symmetric Dim x Dim matrix's determinant and its product with a vector by the inverse (Cramer).
template <int Dim>
struct SymmetricSolve {
  // m[d][e] for e >= d only is read.
  static bool solve(const std::array<std::array<double, Dim>, Dim>& m, const std::array<double, Dim>& b,
                    std::array<double, Dim>& x) {
    double trace = 0.0;
    for (int d = 0; d < Dim; ++d) trace += m[d][d];
    if (!(trace > 0.0)) return false;
    const double scale = trace / Dim;  // about 1 with a full support
    if constexpr (Dim == 2) {
      const double a = m[0][0], c = m[0][1], e = m[1][1];
      const double det = a * e - c * c;
      if (!(det > 0.01 * scale * scale)) return false;
      x[0] = (e * b[0] - c * b[1]) / det;
      x[1] = (a * b[1] - c * b[0]) / det;
    } else {
      const double a = m[0][0], b01 = m[0][1], b02 = m[0][2], e = m[1][1], f = m[1][2], i = m[2][2];
      const double c00 = e * i - f * f, c01 = b02 * f - b01 * i, c02 = b01 * f - b02 * e;
      const double c11 = a * i - b02 * b02, c12 = b01 * b02 - a * f, c22 = a * e - b01 * b01;
      const double det = a * c00 + b01 * c01 + b02 * c02;
      if (!(det > 0.01 * scale * scale * scale)) return false;
      x[0] = (c00 * b[0] + c01 * b[1] + c02 * b[2]) / det;
      x[1] = (c01 * b[0] + c11 * b[1] + c12 * b[2]) / det;
      x[2] = (c02 * b[0] + c12 * b[1] + c22 * b[2]) / det;
    }
    return true;
  }
};

// <grad rho> of every fluid particle (0 for wall particles and where M is near singular), from the
// sums of the pair loop (physics/density_gradient_pair-inl.hpp, compiled per instruction set).
template <int Dim>
class DensityGradient {
 public:
  static constexpr std::size_t kMatrix = Dim * (Dim + 1) / 2;

  // `fluid` is 1 for fluid, 0 for wall particles; `grid` binned on the particles' current order. The
  // same bit for bit on any number of threads.
  void compute(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel, double mass,
               const double* fluid, int threads) {
    const std::size_t n = p.size();
    std::array<double*, kMatrix + Dim> out{};
    for (std::size_t k = 0; k < out.size(); ++k) {
      sums_[k].resize(n);
      out[k] = sums_[k].data();
    }
    for (auto& g : gradient_) g.resize(n);
    density_gradient_sums(p, grid, kernel, mass, fluid, out, threads);
    parallel::for_chunks(static_cast<long>(n), threads, [&](long begin, long end) {
      for (long i = begin; i < end; ++i) {
        std::array<std::array<double, Dim>, Dim> m{};
        std::array<double, Dim> g{}, x{};
        std::size_t k = 0;
        for (int a = 0; a < Dim; ++a)
          for (int b = a; b < Dim; ++b) m[a][b] = sums_[k++][i];
        for (int d = 0; d < Dim; ++d) g[d] = sums_[kMatrix + d][i];
        if (!(fluid[i] != 0.0 && SymmetricSolve<Dim>::solve(m, g, x))) x.fill(0.0);
        for (int d = 0; d < Dim; ++d) gradient_[d][i] = x[d];
      }
    });
  }

  [[nodiscard]] const std::array<std::vector<double>, Dim>& gradient() const { return gradient_; }
  // With several processes: the ghosts' values from their owners.
  [[nodiscard]] std::array<std::vector<double>, Dim>& gradient() { return gradient_; }

 private:
  std::array<std::vector<double>, kMatrix + Dim> sums_;
  std::array<std::vector<double>, Dim> gradient_;
};

}  // namespace sluice
