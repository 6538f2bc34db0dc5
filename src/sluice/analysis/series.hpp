// Time series and the measurements made on them: interpolation, differences against reference data,
// straight-line fits, threshold crossings, periods of an oscillation and the observed order of
// convergence. Plain functions of plain vectors, so that each can be tested on data with a known answer.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace sluice::analysis {

// A measurement that cannot be made (too few samples, a signal that never crosses, bad input).
struct AnalysisError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// y(t) sampled at increasing times t.
struct Series {
  std::vector<double> t;
  std::vector<double> y;
  [[nodiscard]] std::size_t size() const { return t.size(); }
  [[nodiscard]] bool empty() const { return t.empty(); }
};

// Sorts by time and checks that t and y have the same length and hold finite numbers. Samples with
// equal times are kept in their original order (digitised data often has such pairs).
Series sorted(Series s);

// Linear interpolation at time t; nullopt outside [t.front(), t.back()].
std::optional<double> interpolate(const Series& s, double t);

// The simulation interpolated at the reference's times in [t_min, t_max] and compared with it.
struct Difference {
  double rms = 0.0;           // root mean square of (simulation - reference)
  double max_abs = 0.0;       // largest |simulation - reference|
  double mean = 0.0;          // mean of (simulation - reference): the bias
  std::size_t points = 0;     // reference points used
};
// Throws AnalysisError when no reference point in the window is covered by the simulation.
Difference compare(const Series& simulation, const Series& reference, double t_min, double t_max);

// Least-squares straight line y = intercept + slope t through the samples with t in [t_min, t_max].
struct LineFit {
  double slope = 0.0;
  double intercept = 0.0;
  std::size_t points = 0;
};
LineFit fit_line(const Series& s, double t_min, double t_max);

// First time at or after t_from at which y reaches `level` going up (y >= level), linearly
// interpolated between the two samples around it; nullopt if it never does.
std::optional<double> first_rise_to(const Series& s, double level, double t_from = -1e300);

// How far `later` runs behind `reference`: the shift s in [-max_shift, max_shift] (in steps of `step`)
// that minimises the RMS of later(t + s) - reference(t) over the reference's samples with t in
// [t_min, t_max] (those where later(t + s) is covered count). Positive: `later` shows the same values s
// later. Throws AnalysisError when no shift covers a sample.
struct Lag {
  double shift = 0.0;
  double rms = 0.0;  // at that shift
};
Lag best_lag(const Series& later, const Series& reference, double t_min, double t_max, double max_shift, double step);

// Times at which y - mean crosses zero (either direction), linearly interpolated, for t >= t_from.
std::vector<double> zero_crossings(const Series& s, double mean, double t_from = -1e300);

// Period of an oscillation from its zero crossings about its mean over t >= t_from: the time from
// the first to the last crossing divided by the number of half-periods between them. Throws when
// there are fewer than three crossings (one full period).
struct PeriodEstimate {
  double period = 0.0;
  std::size_t crossings = 0;  // zero crossings used
  double t_first = 0.0, t_last = 0.0;
};
PeriodEstimate period_from_zero_crossings(const Series& s, double t_from = -1e300);

// Period from the autocorrelation of the signal (resampled uniformly at the median sample spacing,
// its mean removed): the lag of the peak of the first positive lobe after the autocorrelation first
// falls below zero, refined by a parabola through the peak and its neighbours. Throws when there is no
// such peak within half the record.
double period_from_autocorrelation(const Series& s, double t_from = -1e300);

// Observed order of convergence between two errors measured at spacings dx_coarse > dx_fine:
// p = log(e_coarse / e_fine) / log(dx_coarse / dx_fine).
double observed_order(double error_coarse, double dx_coarse, double error_fine, double dx_fine);

}  // namespace sluice::analysis
