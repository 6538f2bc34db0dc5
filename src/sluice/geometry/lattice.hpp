// The particle lattice: points anchor + (i + 1/2) dx along each axis.
#pragma once

#include <cmath>
#include <vector>

#include "sluice/core/vec.hpp"

namespace sluice {

// Lattice points anchor + (i + 1/2) dx along one axis, for those strictly inside (lo, hi).
inline std::vector<double> lattice(double anchor, double lo, double hi, double dx) {
  std::vector<double> v;
  const long first = static_cast<long>(std::floor((lo - anchor) / dx - 0.5));
  const long last = static_cast<long>(std::ceil((hi - anchor) / dx - 0.5));
  for (long i = first; i <= last; ++i) {
    const double x = anchor + (static_cast<double>(i) + 0.5) * dx;
    if (x > lo && x < hi) v.push_back(x);
  }
  return v;
}

// Calls f(x) for the points of the product of the axes' lattices, the first axis fastest.
template <int Dim, class F>
void for_each_product_point(const std::array<std::vector<double>, Dim>& axes, F&& f) {
  std::array<std::size_t, Dim> k{};
  for (int d = 0; d < Dim; ++d)
    if (axes[d].empty()) return;
  while (true) {
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = axes[d][k[d]];
    f(x);
    int d = 0;
    while (d < Dim && ++k[d] == axes[d].size()) k[d++] = 0;
    if (d == Dim) return;
  }
}

// The lattice anchored at `anchor` strictly inside the box (lo, hi), the first axis fastest.
template <int Dim, class F>
void for_each_lattice_point(const Vec<Dim>& anchor, const Vec<Dim>& lo, const Vec<Dim>& hi, double dx, F&& f) {
  std::array<std::vector<double>, Dim> axes;
  for (int d = 0; d < Dim; ++d) axes[d] = lattice(anchor[d], lo[d], hi[d], dx);
  for_each_product_point<Dim>(axes, f);
}

}  // namespace sluice
