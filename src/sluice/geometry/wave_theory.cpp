#include "sluice/geometry/wave_theory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
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
  return height * height / (32.0 * depth) * (2.0 / n - 3.0 * std::cosh(kh) / (s * s * s));
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

double jonswap_shape(double f, double fp, double gamma) {
  if (!(f > 0.0)) return 0.0;
  const double sigma = f <= fp ? 0.07 : 0.09;
  const double x = f / fp - 1.0, q = fp / f;
  const double r = std::exp(-x * x / (2.0 * sigma * sigma));
  return std::pow(f, -5.0) * std::exp(-1.25 * q * q * q * q) * std::pow(gamma, r);
}

namespace {

// The continuous spectrum's shape integrated over f in [lo, hi] by Simpson's rule in u = ln f, on
// which the peak is a few hundred intervals wide.
double shape_integral(double lo, double hi, double fp, double gamma) {
  constexpr int intervals = 20000;  // even
  const double a = std::log(lo), b = std::log(hi), h = (b - a) / intervals;
  double sum = 0.0;
  for (int i = 0; i <= intervals; ++i) {
    const double f = std::exp(a + i * h);
    const double weight = i == 0 || i == intervals ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += weight * jonswap_shape(f, fp, gamma) * f;  // df = f du
  }
  return sum * h / 3.0;
}

}  // namespace

IrregularSea jonswap_sea(double significant_height, double peak_period, double gamma, int components,
                         std::uint64_t seed) {
  if (!(significant_height > 0.0) || !(peak_period > 0.0) || !(gamma >= 1.0) || components < 1)
    throw std::invalid_argument(
        "jonswap_sea: the significant height and peak period must be positive, gamma at least 1, and there must be "
        "at least one component");
  IrregularSea sea;
  const double fp = 1.0 / peak_period;
  sea.peak_frequency = fp;
  const long bins_per_fp = std::max(1L, std::lround(components / 2.5));
  const long first = std::max(1L, std::lround(0.5 * static_cast<double>(bins_per_fp)));
  sea.df = fp / static_cast<double>(bins_per_fp);
  double shape_sum = 0.0;
  std::mt19937_64 engine(seed);
  for (int n = 0; n < components; ++n) {
    WaveComponent c;
    c.frequency = static_cast<double>(first + n) * sea.df;
    c.amplitude = jonswap_shape(c.frequency, fp, gamma);  // the shape for now; the amplitude below
    c.phase = 2.0 * std::numbers::pi * static_cast<double>(engine() >> 11) * 0x1p-53;
    shape_sum += c.amplitude * sea.df;
    sea.components.push_back(c);
  }
  // C: sum C shape(f_j) df = m0 = Hs^2 / 16.
  const double scale = significant_height * significant_height / 16.0 / shape_sum;
  for (WaveComponent& c : sea.components) c.amplitude = std::sqrt(2.0 * scale * c.amplitude * sea.df);
  // The band's share of the whole spectrum: below fp/5 the shape is below 1e-60 of its peak; above
  // 50 fp it is f^-5 (to 1e-6) and its integral from there is 1 / (4 f^4).
  const double lo = std::max(0.2 * fp, sea.components.front().frequency - 0.5 * sea.df);
  const double hi = sea.components.back().frequency + 0.5 * sea.df;
  const double top = 50.0 * fp;
  const double whole = shape_integral(0.2 * fp, top, fp, gamma) + 0.25 / std::pow(top, 4.0);
  sea.band_share = shape_integral(lo, hi, fp, gamma) / whole;
  return sea;
}

double zeroth_moment(const IrregularSea& sea) {
  double m0 = 0.0;
  for (const WaveComponent& c : sea.components) m0 += 0.5 * c.amplitude * c.amplitude;
  return m0;
}

double share_longer_than(const IrregularSea& sea, double shortest, double depth, double g) {
  double inside = 0.0, all = 0.0;
  for (const WaveComponent& c : sea.components) {
    const double e = 0.5 * c.amplitude * c.amplitude;
    all += e;
    if (2.0 * std::numbers::pi / wavenumber(2.0 * std::numbers::pi * c.frequency, depth, g) >= shortest) inside += e;
  }
  return all > 0.0 ? inside / all : 0.0;
}

}  // namespace sluice::waves
