// Tait equation of state (Monaghan 1994; Batchelor 1967): P = B((rho/rho0)^gamma - 1), B = rho0 c0^2 / gamma.
#pragma once

#include <cmath>

namespace sluice {

struct TaitEos {
  double rest_density;
  double sound_speed;  // c0
  double gamma;

  [[nodiscard]] double stiffness() const { return rest_density * sound_speed * sound_speed / gamma; }

  [[nodiscard]] double pressure(double density) const {
    return stiffness() * (ipow_gamma(density / rest_density) - 1.0);
  }

  // Inverse: the density at which the pressure is p. A tension of B or more (p <= -B) is reached only
  // as the density goes to zero: 0 there (the power of a negative number would be NaN).
  [[nodiscard]] double density(double p) const {
    const double ratio = 1.0 + p / stiffness();
    return ratio > 0.0 ? rest_density * std::pow(ratio, 1.0 / gamma) : 0.0;
  }

  // Local speed of sound c = c0 (rho/rho0)^((gamma-1)/2).
  [[nodiscard]] double local_sound_speed(double density) const {
    return sound_speed * std::sqrt(std::pow(density / rest_density, gamma - 1.0));
  }

 private:
  // gamma = 7 is the common case; avoid pow() in the hot loop for it.
  [[nodiscard]] double ipow_gamma(double x) const {
    if (gamma == 7.0) {
      const double x2 = x * x;
      return x2 * x2 * x2 * x;
    }
    return std::pow(x, gamma);
  }
};

}  // namespace sluice
