// Small fixed-size vectors for geometry and case data (not for particle storage, which is SoA).
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

namespace sluice {

template <int Dim>
using Vec = std::array<double, Dim>;

using Vec2 = Vec<2>;

template <std::size_t Dim>
constexpr Vec<Dim> operator+(Vec<Dim> a, const Vec<Dim>& b) {
  for (std::size_t d = 0; d < Dim; ++d) a[d] += b[d];
  return a;
}

template <std::size_t Dim>
constexpr Vec<Dim> operator-(Vec<Dim> a, const Vec<Dim>& b) {
  for (std::size_t d = 0; d < Dim; ++d) a[d] -= b[d];
  return a;
}

template <std::size_t Dim>
constexpr Vec<Dim> operator*(double s, Vec<Dim> a) {
  for (std::size_t d = 0; d < Dim; ++d) a[d] *= s;
  return a;
}

template <std::size_t Dim>
constexpr double dot(const Vec<Dim>& a, const Vec<Dim>& b) {
  double s = 0.0;
  for (std::size_t d = 0; d < Dim; ++d) s += a[d] * b[d];
  return s;
}

template <std::size_t Dim>
inline double norm(const Vec<Dim>& a) {
  return std::sqrt(dot(a, a));
}

}  // namespace sluice
