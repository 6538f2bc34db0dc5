// Regular waves at wave gauges: the measurements a wave flume is judged by. Per gauge, over a window
// of steady waves: the height and period by zero crossings, and the amplitudes and phases of the first
// harmonics by a least-squares fit; along the flume, the decay of the first harmonic per wavelength;
// from two or more gauges, the incident and reflected waves (Goda & Suzuki 1976 for two gauges, the
// least-squares form of Mansard & Funke 1980 for more). Plain functions of plain vectors, each
// tested on signals with a known answer.
#pragma once

#include <complex>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"

namespace sluice::analysis {

// Zero-crossing analysis of eta over [t0, t1]: the waves between successive up-crossings of the
// window's mean, each wave's height its crest minus its trough and its period the time between them.
struct ZeroCrossingWaves {
  std::size_t waves = 0;
  double mean_height = 0.0, mean_period = 0.0;
  double height_spread = 0.0;  // standard deviation of the heights
};
// Throws AnalysisError when the window holds less than one whole wave.
ZeroCrossingWaves zero_crossing_waves(const Series& eta, double t0, double t1);

// eta(t) = mean + sum_n A_n cos(n omega t - phi_n), n = 1..count, fitted by least squares to the
// samples in [t0, t1]. The phase phi_n grows along a wave travelling to +x (phi_1 = k x + const), in
// [0, 2 pi). `complex(n)` = A_n exp(-i phi_n), so that eta's n-th harmonic is Re(complex(n) e^{i n omega t}).
struct Harmonics {
  double omega = 0.0, mean = 0.0;
  std::vector<double> amplitude, phase;  // [0] is the first harmonic
  double rms_residual = 0.0;             // of the fit
  std::size_t samples = 0;
  [[nodiscard]] std::complex<double> complex(int n) const;
};
// With `background` > 0 the mean is a polynomial of that degree in time (up to 3) fitted alongside
// (a slow motion of its own under the harmonics, such as a moored body's drift), and `mean` is its
// value at the window's middle.
// Throws AnalysisError with fewer samples than 2 count + background + 2, or a window shorter than one
// period.
Harmonics fit_harmonics(const Series& eta, double omega, int count, double t0, double t1, int background = 0);

// The first harmonics Z_m = Re-part amplitudes at gauges x_m split into an incident wave I e^{-i k x}
// and a reflected one R e^{i k x}: the least-squares solution over the gauges (exact for two).
struct IncidentReflected {
  double incident = 0.0, reflected = 0.0;  // amplitudes |I|, |R|
  double coefficient = 0.0;                // |R| / |I|
  double residual = 0.0;                   // rms of Z_m - (I e^{-ikx} + R e^{ikx}) over the gauges (0 for two)
  // The separation is ill-conditioned when the gauges' spacings are near a multiple of half a
  // wavelength (Goda & Suzuki ask for 0.05 < spacing/L < 0.45 between two gauges): the smallest
  // singular value's share of the largest, 0 (singular) to 1.
  double conditioning = 0.0;
};
// Throws AnalysisError with fewer than two gauges or k <= 0.
IncidentReflected separate_incident_reflected(const std::vector<double>& x, const std::vector<std::complex<double>>& z,
                                              double k);

// A(x) = A0 exp(-beta x) fitted to the first-harmonic amplitudes at positions x (least squares on
// log A); per_wavelength = 1 - exp(-beta L), the fraction lost over one wavelength (negative: growth).
struct Decay {
  double per_wavelength = 0.0;
  double a0 = 0.0, beta = 0.0;
  std::size_t gauges = 0;
};
// Throws AnalysisError with fewer than two gauges, or a non-positive amplitude.
Decay amplitude_decay(const std::vector<double>& x, const std::vector<double>& amplitude, double wavelength);

// The mean of y over the samples with t <= until (at least the first sample): a gauge's still level
// before the waves reach it. Throws AnalysisError for an empty series.
double mean_before(const Series& s, double until);

// When a gauge at distance `distance` from the wave maker sees steady waves: after the maker's start,
// its ramp and the front's travel at the group velocity, plus `settle` periods for the front's tail;
// and until `end`, or until the first reflection from a wall `reflector` metres from the maker
// returns (nullopt: an absorbing end), less one period. The window is cut to whole periods.
struct Window {
  double t0 = 0.0, t1 = 0.0;
  [[nodiscard]] double periods(double period) const { return (t1 - t0) / period; }
};
// nullopt if less than `min_periods` whole periods of steady waves reach the gauge before `end`.
std::optional<Window> steady_window(double distance, double start, double ramp_time, double group_velocity, double period,
                                    double end, std::optional<double> reflector, double settle = 2.0,
                                    double min_periods = 2.0);

}  // namespace sluice::analysis
