#include "sluice/analysis/series.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace sluice::analysis {

Series sorted(Series s) {
  if (s.t.size() != s.y.size())
    throw AnalysisError(fmt::format("a series has {} times but {} values", s.t.size(), s.y.size()));
  for (std::size_t i = 0; i < s.t.size(); ++i)
    if (!std::isfinite(s.t[i]) || !std::isfinite(s.y[i]))
      throw AnalysisError(fmt::format("a series has a non-finite sample ({}, {}) at row {}", s.t[i], s.y[i], i));
  std::vector<std::size_t> order(s.t.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return s.t[a] < s.t[b]; });
  Series out;
  for (std::size_t i : order) {
    out.t.push_back(s.t[i]);
    out.y.push_back(s.y[i]);
  }
  return out;
}

std::optional<double> interpolate(const Series& s, double t) {
  if (s.empty() || t < s.t.front() || t > s.t.back()) return std::nullopt;
  const auto hi = static_cast<std::size_t>(std::lower_bound(s.t.begin(), s.t.end(), t) - s.t.begin());
  if (s.t[hi] == t || hi == 0) return s.y[hi];
  const std::size_t lo = hi - 1;
  const double w = (t - s.t[lo]) / (s.t[hi] - s.t[lo]);
  return s.y[lo] + w * (s.y[hi] - s.y[lo]);
}

Difference compare(const Series& simulation, const Series& reference, double t_min, double t_max) {
  Difference d;
  double sum2 = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double t = reference.t[i];
    if (t < t_min || t > t_max) continue;
    const auto value = interpolate(simulation, t);
    if (!value) continue;
    const double e = *value - reference.y[i];
    sum2 += e * e;
    sum += e;
    d.max_abs = std::max(d.max_abs, std::abs(e));
    ++d.points;
  }
  if (d.points == 0)
    throw AnalysisError(fmt::format(
        "no reference point with {} <= t <= {} lies within the simulated times [{}, {}]", t_min, t_max,
        simulation.empty() ? 0.0 : simulation.t.front(), simulation.empty() ? 0.0 : simulation.t.back()));
  d.rms = std::sqrt(sum2 / static_cast<double>(d.points));
  d.mean = sum / static_cast<double>(d.points);
  return d;
}

LineFit fit_line(const Series& s, double t_min, double t_max) {
  double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
  LineFit f;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.t[i] < t_min || s.t[i] > t_max) continue;
    st += s.t[i];
    sy += s.y[i];
    stt += s.t[i] * s.t[i];
    sty += s.t[i] * s.y[i];
    ++f.points;
  }
  const auto n = static_cast<double>(f.points);
  const double denominator = n * stt - st * st;
  if (f.points < 2 || !(std::abs(denominator) > 1e-300))
    throw AnalysisError(fmt::format("a straight line needs two samples at different times in [{}, {}]; found {}",
                                    t_min, t_max, f.points));
  f.slope = (n * sty - st * sy) / denominator;
  f.intercept = (sy - f.slope * st) / n;
  return f;
}

std::optional<double> first_rise_to(const Series& s, double level, double t_from) {
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.t[i] < t_from || s.y[i] < level) continue;
    if (i == 0 || s.t[i - 1] < t_from || s.y[i - 1] >= level) return s.t[i];
    const double w = (level - s.y[i - 1]) / (s.y[i] - s.y[i - 1]);
    return s.t[i - 1] + w * (s.t[i] - s.t[i - 1]);
  }
  return std::nullopt;
}

Lag best_lag(const Series& later, const Series& reference, double t_min, double t_max, double max_shift, double step) {
  if (!(step > 0.0) || !(max_shift >= 0.0)) throw AnalysisError("best_lag: the step must be positive and the range not negative");
  Lag best{0.0, std::numeric_limits<double>::infinity()};
  const long steps = std::lround(max_shift / step);
  Series shifted = later;
  for (long k = -steps; k <= steps; ++k) {
    const double shift = static_cast<double>(k) * step;
    for (std::size_t i = 0; i < later.size(); ++i) shifted.t[i] = later.t[i] - shift;  // shifted(t) = later(t + shift)
    const bool covered = std::any_of(reference.t.begin(), reference.t.end(), [&](double t) {
      return t >= t_min && t <= t_max && !shifted.empty() && t >= shifted.t.front() && t <= shifted.t.back();
    });
    if (!covered) continue;
    const double rms = compare(shifted, reference, t_min, t_max).rms;
    if (rms < best.rms) best = {shift, rms};
  }
  if (!std::isfinite(best.rms)) throw AnalysisError("best_lag: no shift leaves a reference sample covered");
  return best;
}

std::vector<double> zero_crossings(const Series& s, double mean, double t_from) {
  std::vector<double> out;
  for (std::size_t i = 1; i < s.size(); ++i) {
    if (s.t[i - 1] < t_from) continue;
    const double a = s.y[i - 1] - mean, b = s.y[i] - mean;
    // A sample exactly at the mean counts once: as the end of a sign change, not as its start.
    if ((a < 0.0 && b >= 0.0) || (a > 0.0 && b <= 0.0))
      out.push_back(s.t[i - 1] + (s.t[i] - s.t[i - 1]) * a / (a - b));
  }
  return out;
}

namespace {

double mean_from(const Series& s, double t_from) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.t[i] >= t_from) {
      sum += s.y[i];
      ++n;
    }
  if (n == 0) throw AnalysisError(fmt::format("no samples at or after t = {}", t_from));
  return sum / static_cast<double>(n);
}

}  // namespace

PeriodEstimate period_from_zero_crossings(const Series& s, double t_from) {
  const std::vector<double> crossings = zero_crossings(s, mean_from(s, t_from), t_from);
  if (crossings.size() < 3)
    throw AnalysisError(fmt::format("the signal crosses its mean {} time{} after t = {}; a period needs at least 3",
                                    crossings.size(), crossings.size() == 1 ? "" : "s", t_from));
  PeriodEstimate p;
  p.crossings = crossings.size();
  p.t_first = crossings.front();
  p.t_last = crossings.back();
  p.period = 2.0 * (p.t_last - p.t_first) / static_cast<double>(crossings.size() - 1);
  return p;
}

double period_from_autocorrelation(const Series& s, double t_from) {
  std::vector<double> spacing;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s.t[i - 1] >= t_from && s.t[i] > s.t[i - 1]) spacing.push_back(s.t[i] - s.t[i - 1]);
  if (spacing.size() < 8) throw AnalysisError("an autocorrelation needs at least 8 samples");
  std::nth_element(spacing.begin(), spacing.begin() + static_cast<long>(spacing.size() / 2), spacing.end());
  const double step = spacing[spacing.size() / 2];
  double t0 = t_from;
  for (double t : s.t)
    if (t >= t_from) {
      t0 = t;
      break;
    }
  std::vector<double> u;
  for (double t = t0; t <= s.t.back() + 1e-9 * step; t += step) u.push_back(*interpolate(s, std::min(t, s.t.back())));
  const double mean = std::accumulate(u.begin(), u.end(), 0.0) / static_cast<double>(u.size());
  for (double& v : u) v -= mean;
  const std::size_t n = u.size();
  // Normalised by the number of overlapping samples, so that long lags are not biased low.
  auto correlation = [&](std::size_t lag) {
    double sum = 0.0;
    for (std::size_t i = 0; i + lag < n; ++i) sum += u[i] * u[i + lag];
    return sum / static_cast<double>(n - lag);
  };
  std::vector<double> r(n / 2 + 1);
  for (std::size_t lag = 0; lag < r.size(); ++lag) r[lag] = correlation(lag);
  // The period is the lag of the first positive lobe after the autocorrelation first falls below zero
  // (later lobes, at multiples of the period, are as high for a steady oscillation).
  std::size_t lag = 1;
  while (lag < r.size() && r[lag] > 0.0) ++lag;
  if (lag >= r.size()) throw AnalysisError("the autocorrelation does not fall to zero within half the record");
  while (lag < r.size() && r[lag] <= 0.0) ++lag;
  std::size_t best = lag;
  for (std::size_t k = lag; k < r.size() && r[k] > 0.0; ++k)
    if (r[k] > r[best]) best = k;
  if (best + 1 >= r.size() || !(r[best] > 0.0))
    throw AnalysisError("the autocorrelation has no positive peak within half the record; the record is too short");
  const double a = r[best - 1], b = r[best], c = r[best + 1];
  const double denominator = a - 2.0 * b + c;
  const double shift = std::abs(denominator) > 0.0 ? 0.5 * (a - c) / denominator : 0.0;
  return (static_cast<double>(best) + shift) * step;
}

double observed_order(double error_coarse, double dx_coarse, double error_fine, double dx_fine) {
  if (!(error_coarse > 0.0) || !(error_fine > 0.0))
    throw AnalysisError(fmt::format("an observed order needs positive errors (got {} and {})", error_coarse, error_fine));
  if (!(dx_coarse > dx_fine) || !(dx_fine > 0.0))
    throw AnalysisError(fmt::format("an observed order needs dx_coarse > dx_fine > 0 (got {} and {})", dx_coarse, dx_fine));
  return std::log(error_coarse / error_fine) / std::log(dx_coarse / dx_fine);
}

}  // namespace sluice::analysis
