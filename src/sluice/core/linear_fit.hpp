// A first-order (linear) fit of a field around a point x from scattered samples: the function
// a + b . y, y = (x_j - x) / h, fitted to the samples f_j by least squares with weights w_j (in SPH,
// w_j = V_j W(|x_j - x|)). It reproduces a linear field exactly, even when the samples lie on one side
// of x, as they do next to a wall; the Shepard average sum w f / sum w is its zeroth-order fallback.
//
// Used by the pressure probes (io/probes.cpp) and the ghost nodes of the mDBC walls
// (physics/mdbc.hpp). The moments are public so that a caller can reduce them across processes
// before solving.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <utility>

namespace sluice {

template <int Dim>
struct LinearFit {
  static constexpr int M = Dim + 1;  // unknowns: a and the Dim components of b
  // moments[a][b] = sum w y_a y_b and rhs[a] = sum w f y_a, with y_0 = 1.
  std::array<std::array<double, M>, M> moments{};
  std::array<double, M> rhs{};

  void add(double w, const std::array<double, Dim>& y, double f) {
    std::array<double, M> ya{1.0};
    for (int d = 0; d < Dim; ++d) ya[d + 1] = y[d];
    for (int a = 0; a < M; ++a) {
      rhs[a] += w * f * ya[a];
      for (int b = 0; b < M; ++b) moments[a][b] += w * ya[a] * ya[b];
    }
  }

  [[nodiscard]] double weight() const { return moments[0][0]; }
  // The Shepard (zeroth-order) value; requires weight() > 0.
  [[nodiscard]] double shepard() const { return rhs[0] / moments[0][0]; }

  // The fitted (a, b): Gaussian elimination with partial pivoting on the moments normalised by the
  // weight sum. Empty when the fit is ill-posed: no weight, or a pivot below `tiny` (the samples do
  // not span the space: a single point, or all in a line).
  [[nodiscard]] std::optional<std::array<double, M>> solve(double tiny = 1e-6) const {
    if (!(weight() > 0.0)) return std::nullopt;
    auto m = moments;
    auto f = rhs;
    const double inv_weight = 1.0 / weight();
    for (int a = 0; a < M; ++a) {
      f[a] *= inv_weight;
      for (int b = 0; b < M; ++b) m[a][b] *= inv_weight;
    }
    for (int c = 0; c < M; ++c) {
      int pivot = c;
      for (int a = c + 1; a < M; ++a)
        if (std::abs(m[a][c]) > std::abs(m[pivot][c])) pivot = a;
      if (std::abs(m[pivot][c]) < tiny) return std::nullopt;
      std::swap(m[c], m[pivot]);
      std::swap(f[c], f[pivot]);
      for (int a = c + 1; a < M; ++a) {
        const double factor = m[a][c] / m[c][c];
        for (int b = c; b < M; ++b) m[a][b] -= factor * m[c][b];
        f[a] -= factor * f[c];
      }
    }
    std::array<double, M> coef{};
    for (int a = M - 1; a >= 0; --a) {
      double rest = f[a];
      for (int b = a + 1; b < M; ++b) rest -= m[a][b] * coef[b];
      coef[a] = rest / m[a][a];
    }
    return coef;
  }
};

}  // namespace sluice
