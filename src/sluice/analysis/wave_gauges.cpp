#include "sluice/analysis/wave_gauges.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sluice::analysis {

namespace {

// The samples of s with t in [t0, t1].
std::pair<std::size_t, std::size_t> window_indices(const Series& s, double t0, double t1) {
  const auto begin = static_cast<std::size_t>(std::lower_bound(s.t.begin(), s.t.end(), t0) - s.t.begin());
  const auto end = static_cast<std::size_t>(std::upper_bound(s.t.begin(), s.t.end(), t1) - s.t.begin());
  return {begin, std::max(begin, end)};
}

// Solves the symmetric positive definite system a x = b (n x n, row-major) by Gaussian elimination
// with partial pivoting; nullopt when it is singular to round-off.
std::optional<std::vector<double>> solve(std::vector<double> a, std::vector<double> b) {
  const std::size_t n = b.size();
  double scale = 0.0;
  for (double v : a) scale = std::max(scale, std::abs(v));
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < n; ++r)
      if (std::abs(a[r * n + col]) > std::abs(a[pivot * n + col])) pivot = r;
    if (!(std::abs(a[pivot * n + col]) > 1e-13 * scale)) return std::nullopt;
    if (pivot != col) {
      for (std::size_t c = 0; c < n; ++c) std::swap(a[col * n + c], a[pivot * n + c]);
      std::swap(b[col], b[pivot]);
    }
    for (std::size_t r = col + 1; r < n; ++r) {
      const double f = a[r * n + col] / a[col * n + col];
      for (std::size_t c = col; c < n; ++c) a[r * n + c] -= f * a[col * n + c];
      b[r] -= f * b[col];
    }
  }
  std::vector<double> x(n);
  for (std::size_t r = n; r-- > 0;) {
    double v = b[r];
    for (std::size_t c = r + 1; c < n; ++c) v -= a[r * n + c] * x[c];
    x[r] = v / a[r * n + r];
  }
  return x;
}

}  // namespace

ZeroCrossingWaves zero_crossing_waves(const Series& eta, double t0, double t1) {
  const auto [begin, end] = window_indices(eta, t0, t1);
  if (end - begin < 3) throw AnalysisError(fmt::format("zero crossings: fewer than 3 samples in [{}, {}] s", t0, t1));
  double mean = 0.0;
  for (std::size_t i = begin; i < end; ++i) mean += eta.y[i];
  mean /= static_cast<double>(end - begin);
  // Up-crossings of the mean, linearly interpolated, and the index after each.
  std::vector<double> crossing;
  std::vector<std::size_t> after;
  for (std::size_t i = begin + 1; i < end; ++i) {
    const double a = eta.y[i - 1] - mean, b = eta.y[i] - mean;
    if (a < 0.0 && b >= 0.0) {
      crossing.push_back(eta.t[i - 1] + (eta.t[i] - eta.t[i - 1]) * (-a) / (b - a));
      after.push_back(i);
    }
  }
  if (crossing.size() < 2)
    throw AnalysisError(fmt::format("zero crossings: less than one whole wave in [{}, {}] s", t0, t1));
  ZeroCrossingWaves w;
  std::vector<double> heights;
  for (std::size_t k = 0; k + 1 < crossing.size(); ++k) {
    double lo = eta.y[after[k]], hi = lo;
    for (std::size_t i = after[k]; i < after[k + 1]; ++i) {
      lo = std::min(lo, eta.y[i]);
      hi = std::max(hi, eta.y[i]);
    }
    heights.push_back(hi - lo);
  }
  w.waves = heights.size();
  for (double h : heights) w.mean_height += h;
  w.mean_height /= static_cast<double>(w.waves);
  for (double h : heights) w.height_spread += (h - w.mean_height) * (h - w.mean_height);
  w.height_spread = std::sqrt(w.height_spread / static_cast<double>(w.waves));
  w.mean_period = (crossing.back() - crossing.front()) / static_cast<double>(w.waves);
  return w;
}

std::complex<double> Harmonics::complex(int n) const {
  const auto k = static_cast<std::size_t>(n - 1);
  return std::polar(amplitude.at(k), -phase.at(k));
}

Harmonics fit_harmonics(const Series& eta, double omega, int count, double t0, double t1, int background) {
  if (count < 1 || !(omega > 0.0)) throw AnalysisError("harmonics: expected at least one harmonic and omega > 0");
  if (background < 0 || background > 3) throw AnalysisError("harmonics: the background's degree is 0 to 3");
  if (!(t1 - t0 >= 2.0 * std::numbers::pi / omega * (1.0 - 1e-9)))
    throw AnalysisError(fmt::format("harmonics: the window [{}, {}] s is shorter than one period, {} s", t0, t1,
                                    2.0 * std::numbers::pi / omega));
  const auto [begin, end] = window_indices(eta, t0, t1);
  const auto slow = static_cast<std::size_t>(background + 1);
  const auto m = slow + static_cast<std::size_t>(2 * count);
  if (end - begin < m + 1)
    throw AnalysisError(fmt::format("harmonics: {} samples in [{}, {}] s; expected at least {}", end - begin, t0, t1, m + 1));
  // Columns: the background's powers of s (the time from the window's middle over its half length,
  // for conditioning), then cos(n w t), sin(n w t).
  const double middle = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
  std::vector<double> ata(m * m, 0.0), atb(m, 0.0), row(m);
  auto fill = [&](double t) {
    const double s = (t - middle) / half;
    row[0] = 1.0;
    for (std::size_t k = 1; k < slow; ++k) row[k] = row[k - 1] * s;
    for (int n = 1; n <= count; ++n) {
      row[slow + 2 * (n - 1)] = std::cos(n * omega * t);
      row[slow + 2 * (n - 1) + 1] = std::sin(n * omega * t);
    }
  };
  for (std::size_t i = begin; i < end; ++i) {
    fill(eta.t[i]);
    for (std::size_t a = 0; a < m; ++a) {
      atb[a] += row[a] * eta.y[i];
      for (std::size_t b = 0; b < m; ++b) ata[a * m + b] += row[a] * row[b];
    }
  }
  const auto c = solve(ata, atb);
  if (!c) throw AnalysisError(fmt::format("harmonics: the fit over [{}, {}] s is singular", t0, t1));
  Harmonics h;
  h.omega = omega;
  h.mean = (*c)[0];
  h.samples = end - begin;
  for (int n = 1; n <= count; ++n) {
    // a cos + b sin = A cos(n w t - phi)
    const double a = (*c)[slow + 2 * (n - 1)], b = (*c)[slow + 2 * (n - 1) + 1];
    h.amplitude.push_back(std::hypot(a, b));
    double phi = std::atan2(b, a);
    if (phi < 0.0) phi += 2.0 * std::numbers::pi;
    h.phase.push_back(phi);
  }
  double sum2 = 0.0;
  for (std::size_t i = begin; i < end; ++i) {
    fill(eta.t[i]);
    double model = 0.0;
    for (std::size_t a = 0; a < m; ++a) model += row[a] * (*c)[a];
    sum2 += (eta.y[i] - model) * (eta.y[i] - model);
  }
  h.rms_residual = std::sqrt(sum2 / static_cast<double>(h.samples));
  return h;
}

IncidentReflected separate_incident_reflected(const std::vector<double>& x, const std::vector<std::complex<double>>& z,
                                              double k) {
  if (x.size() != z.size() || x.size() < 2)
    throw AnalysisError(fmt::format("reflection: {} gauge positions and {} amplitudes; expected two or more of each",
                                    x.size(), z.size()));
  if (!(k > 0.0)) throw AnalysisError("reflection: expected a wavenumber > 0");
  // Minimise sum |z_m - I a_m - R conj(a_m)|^2, a_m = e^{-i k x_m}: the normal equations
  // [N S; conj(S) N] [I; R] = [sum conj(a) z; sum a z], S = sum e^{2 i k x_m}.
  const auto n = static_cast<double>(x.size());
  std::complex<double> s{}, p{}, q{};
  for (std::size_t m = 0; m < x.size(); ++m) {
    const std::complex<double> a = std::polar(1.0, -k * x[m]);
    s += a * a;  // the (1,2) entry conj(a) b = conj(a) conj(a): summed with its conjugate below
    p += std::conj(a) * z[m];
    q += a * z[m];
  }
  s = std::conj(s);  // sum conj(a_m)^2 = sum e^{2 i k x_m}
  IncidentReflected r;
  r.conditioning = std::sqrt(std::max(0.0, (n - std::abs(s)) / (n + std::abs(s))));
  const double det = n * n - std::norm(s);
  if (!(det > 1e-12 * n * n))
    throw AnalysisError("reflection: the gauges are a whole number of half wavelengths apart; incident and reflected "
                        "waves cannot be told apart there");
  const std::complex<double> incident = (n * p - s * q) / det, reflected = (n * q - std::conj(s) * p) / det;
  r.incident = std::abs(incident);
  r.reflected = std::abs(reflected);
  r.coefficient = r.reflected / r.incident;
  double sum2 = 0.0;
  for (std::size_t m = 0; m < x.size(); ++m) {
    const std::complex<double> a = std::polar(1.0, -k * x[m]);
    sum2 += std::norm(z[m] - incident * a - reflected * std::conj(a));
  }
  r.residual = std::sqrt(sum2 / n);
  return r;
}

Decay amplitude_decay(const std::vector<double>& x, const std::vector<double>& amplitude, double wavelength) {
  if (x.size() != amplitude.size() || x.size() < 2)
    throw AnalysisError(fmt::format("decay: {} positions and {} amplitudes; expected two or more of each", x.size(),
                                    amplitude.size()));
  Series s;
  for (std::size_t m = 0; m < x.size(); ++m) {
    if (!(amplitude[m] > 0.0)) throw AnalysisError(fmt::format("decay: amplitude {} at x = {} m; expected > 0", amplitude[m], x[m]));
    s.t.push_back(x[m]);
    s.y.push_back(std::log(amplitude[m]));
  }
  s = sorted(std::move(s));
  const LineFit line = fit_line(s, s.t.front(), s.t.back());
  Decay d;
  d.beta = -line.slope;
  d.a0 = std::exp(line.intercept);
  d.per_wavelength = 1.0 - std::exp(-d.beta * wavelength);
  d.gauges = x.size();
  return d;
}

std::optional<Window> steady_window(double distance, double start, double ramp_time, double group_velocity, double period,
                                    double end, std::optional<double> reflector, double settle, double min_periods) {
  Window w;
  w.t0 = start + ramp_time + distance / group_velocity + settle * period;
  w.t1 = end;
  if (reflector) w.t1 = std::min(w.t1, start + (2.0 * *reflector - distance) / group_velocity - period);
  const double whole = std::floor((w.t1 - w.t0) / period + 1e-9);
  if (!(whole >= min_periods)) return std::nullopt;
  w.t1 = w.t0 + whole * period;
  return w;
}

double mean_before(const Series& s, double until) {
  if (s.empty()) throw AnalysisError("an empty series has no still level");
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t j = 0; j < s.size() && (s.t[j] <= until || j == 0); ++j, ++n) sum += s.y[j];
  return sum / static_cast<double>(n);
}

}  // namespace sluice::analysis
