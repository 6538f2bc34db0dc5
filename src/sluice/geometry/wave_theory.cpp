#include "sluice/geometry/wave_theory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace sluice::waves {

double wavenumber(double omega, double depth, double g) {
  if (!(omega > 0.0) || !(depth > 0.0) || !(g > 0.0))
    throw std::invalid_argument("wavenumber: the frequency, depth and gravity must be positive");
  // Solve F(x) = x tanh(x) - a = 0 for x = kh, a = omega^2 h / g, by Newton's method. F' >= tanh x > 0,
  // and F is convex for x tanh x < 1 and concave above, so from the larger of the deep-water (x = a) and
  // shallow-water (x = sqrt(a)) roots the iterates converge quadratically (at most one overshoot);
  // stop once a step no longer changes x beyond a few units in the last place.
  const double a = omega * omega * depth / g;
  double x = std::max(a, std::sqrt(a));
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double t = std::tanh(x);
    const double step = (x * t - a) / (t + x * (1.0 - t * t));
    x -= step;
    if (std::abs(step) <= 4.0 * std::numeric_limits<double>::epsilon() * x) break;
  }
  return x / depth;
}

double piston_height_per_stroke(double kh) {
  const double s = std::sinh(kh);
  return 4.0 * s * s / (std::sinh(2.0 * kh) + 2.0 * kh);
}

double flap_height_per_stroke(double k, double depth, double hinge) {
  const double kh = k * depth, d = depth - hinge;
  const double profile = std::sinh(kh) + (std::cosh(k * hinge) - std::cosh(kh)) / (k * d);
  return 4.0 * std::sinh(kh) / (std::sinh(2.0 * kh) + 2.0 * kh) * profile;
}

double madsen_second_order_amplitude(double height, double k, double depth) {
  const double kh = k * depth;
  const double n = 0.5 * (1.0 + 2.0 * kh / std::sinh(2.0 * kh));
  const double s = std::sinh(kh);
  return height * height / (32.0 * depth) * (3.0 * std::cosh(kh) / (s * s * s) - 2.0 / n);
}

RegularWave regular_wave(double height, double period, double depth, double g) {
  RegularWave w;
  w.height = height;
  w.period = period;
  w.depth = depth;
  const double omega = 2.0 * std::numbers::pi / period;
  w.k = wavenumber(omega, depth, g);
  w.wavelength = 2.0 * std::numbers::pi / w.k;
  w.kh = w.k * depth;
  w.steepness = height / w.wavelength;
  w.celerity = w.wavelength / period;
  w.group_velocity = 0.5 * w.celerity * (1.0 + 2.0 * w.kh / std::sinh(2.0 * w.kh));
  w.miche_steepness = 0.142 * std::tanh(w.kh);
  w.ursell = height * w.wavelength * w.wavelength / (depth * depth * depth);
  return w;
}

}  // namespace sluice::waves
