// `sluice analyze` on a flume whose wave maker makes irregular waves (spectrum = "jonswap"): at each
// gauge, over the window after the peak waves' front has passed, the significant height from the
// variance, Hm0 = 4 sqrt(m0), and the peak period of the measured spectrum, against the maker's Hs and
// Tp; a plot of the spectra with the target's.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sluice/analysis/series.hpp"
#include "sluice/analysis/wave_gauges.hpp"
#include "sluice/case/case.hpp"

namespace sluice::analysis {

// One-sided variance spectrum (m^2/Hz) of eta over [t0, t1]: eta linearly resampled at the series'
// median spacing, its mean removed, the periodogram at k / (N dt) for 0 < f <= f_max, averaged over
// `smooth` neighbouring frequencies (a Daniell window). Throws AnalysisError with fewer than 16
// samples in the window.
struct VarianceSpectrum {
  std::vector<double> f, s;
};
VarianceSpectrum variance_spectrum(const Series& eta, double t0, double t1, double f_max, int smooth = 5);

struct IrregularGauge {
  std::string name;
  double x = 0.0, distance = 0.0;
  std::optional<Window> window;
  double hm0 = 0.0, peak_period = 0.0;  // 4 sqrt(variance) over the window; 1 / the spectrum's peak
  VarianceSpectrum spectrum;
  std::string note;
};

struct IrregularAnalysis {
  std::string maker;
  double significant_height = 0.0, peak_period = 0.0, gamma = 0.0, depth = 0.0;
  double repeat_period = 0.0;  // the discretised sea's, 1/df
  double start = 0.0, ramp_time = 0.0, maker_x = 0.0, peak_group_velocity = 0.0;
  VarianceSpectrum target;  // the discretised spectrum, a_n^2 / (2 df) at f_n
  std::vector<IrregularGauge> gauges;
  std::vector<std::string> notes;
};

// Whether the case's wave maker makes irregular waves.
bool has_irregular_maker(const Case& c);

// Throws AnalysisError without such a maker, without gauges, or with a gauge's series missing.
IrregularAnalysis analyze_irregular_flume(const std::filesystem::path& run_dir, const Case& c);

std::string irregular_table(const IrregularAnalysis& a);

// Writes irregular.csv (per gauge: position, window, Hm0, Tp, against the target), spectra.svg and
// report.html into out_dir.
void write_irregular_report(const IrregularAnalysis& a, const std::filesystem::path& run_dir,
                            const std::filesystem::path& out_dir);

}  // namespace sluice::analysis
