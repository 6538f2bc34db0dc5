// The wave-flume measurements on signals with known answers: zero-crossing heights and periods, the
// harmonics' amplitudes and phases, incident and reflected waves from two and three gauges, the decay
// along the flume, the steady window; and `analyze_flume` on a run directory of synthetic gauge series
// (an incident wave with a 10 % reflection), which must find the target's height, no phase lag and the
// reflection; and a paddle driven by a record holding the gauges' measurements, compared with them.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <complex>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "sluice/analysis/irregular_waves.hpp"
#include "sluice/analysis/wave_flume.hpp"
#include "sluice/analysis/wave_gauges.hpp"
#include "sluice/geometry/wave_theory.hpp"
#include "sluice/io/atomic_file.hpp"

using namespace sluice;
using namespace sluice::analysis;
namespace fs = std::filesystem;

namespace {

constexpr double pi = std::numbers::pi;

Series sampled(double t0, double t1, double dt, const std::function<double(double)>& f) {
  Series s;
  for (double t = t0; t <= t1 + 1e-12; t += dt) {
    s.t.push_back(t);
    s.y.push_back(f(t));
  }
  return s;
}

}  // namespace

TEST(WaveGauges, ZeroCrossingsOfASineGiveItsHeightAndPeriod) {
  const double period = 1.3, omega = 2.0 * pi / period;
  const Series eta = sampled(0.0, 20.0, 0.005, [&](double t) { return 0.02 + 0.04 * std::sin(omega * t + 0.3); });
  const ZeroCrossingWaves w = zero_crossing_waves(eta, 2.0, 15.0);
  EXPECT_NEAR(w.mean_period, period, 1e-4);
  EXPECT_NEAR(w.mean_height, 0.08, 1e-4);  // the samples miss the crest by at most 0.04 (1 - cos(omega dt / 2))
  EXPECT_GE(w.waves, 9u);
  EXPECT_LT(w.height_spread, 1e-4);
  EXPECT_THROW(zero_crossing_waves(eta, 2.0, 2.5), AnalysisError);  // less than one wave
}

// Two harmonics and a mean, recovered to round-off over a window that is not a whole number of
// periods; the phase grows along +x as k x.
TEST(WaveGauges, HarmonicsAreFittedToRoundOff) {
  const double omega = 2.0 * pi / 1.2;
  const Series eta = sampled(0.0, 12.0, 0.01, [&](double t) {
    return 0.003 + 0.04 * std::cos(omega * t - 1.1) + 0.005 * std::cos(2.0 * omega * t - 5.9);
  });
  const Harmonics h = fit_harmonics(eta, omega, 2, 3.05, 9.7);
  EXPECT_NEAR(h.mean, 0.003, 1e-13);
  EXPECT_NEAR(h.amplitude[0], 0.04, 1e-13);
  EXPECT_NEAR(h.phase[0], 1.1, 1e-11);
  EXPECT_NEAR(h.amplitude[1], 0.005, 1e-13);
  EXPECT_NEAR(h.phase[1], 5.9, 1e-10);
  EXPECT_LT(h.rms_residual, 1e-14);
  const std::complex<double> z = h.complex(1);
  EXPECT_NEAR(std::real(z * std::polar(1.0, omega * 4.0)), 0.04 * std::cos(omega * 4.0 - 1.1), 1e-13);
  EXPECT_THROW(fit_harmonics(eta, omega, 2, 3.0, 3.5), AnalysisError);  // shorter than a period
}

// A body's slow drift under its wave motion: a straight line under the first harmonic, over a window
// of 4 periods. With a straight-line background the harmonic comes back to round-off (and the
// line's value at the window's middle as the mean); with only a mean the drift leaks into it.
TEST(WaveGauges, ASlowDriftIsFittedApartFromTheHarmonic) {
  const double omega = 2.0 * pi / 1.5, t0 = 10.0, t1 = 16.0;
  const Series x = sampled(0.0, 20.0, 0.01, [&](double t) {
    return 0.002 + 0.0015 * (t - 13.0) + 0.004 * std::cos(omega * t - 0.7);
  });
  const Harmonics line = fit_harmonics(x, omega, 1, t0, t1, 1);
  EXPECT_NEAR(line.amplitude[0], 0.004, 1e-13);
  EXPECT_NEAR(line.phase[0], 0.7, 1e-10);
  EXPECT_NEAR(line.mean, 0.002, 1e-13);
  EXPECT_LT(line.rms_residual, 1e-14);
  const Harmonics mean_only = fit_harmonics(x, omega, 1, t0, t1);
  EXPECT_GT(std::abs(mean_only.phase[0] - 0.7), 0.15);  // radians (10 degrees here): the drift moved it
  EXPECT_GT(mean_only.rms_residual, 1e-4);
  EXPECT_THROW(fit_harmonics(x, omega, 1, t0, t1, 4), AnalysisError);
}

// An incident wave and a reflected one of 30 % at an arbitrary phase: two gauges (Goda & Suzuki) and
// three (least squares) give them back exactly; gauges half a wavelength apart cannot.
TEST(WaveGauges, IncidentAndReflectedWavesAreSeparated) {
  const double k = 2.0 * pi / 2.0;  // L = 2 m
  const std::complex<double> incident = std::polar(0.04, -0.7), reflected = std::polar(0.012, 2.2);
  auto at = [&](double x) { return incident * std::polar(1.0, -k * x) + reflected * std::polar(1.0, k * x); };
  for (const std::vector<double>& x : {std::vector<double>{3.0, 3.5}, std::vector<double>{3.0, 3.35, 3.8}}) {
    std::vector<std::complex<double>> z;
    for (double xm : x) z.push_back(at(xm));
    const IncidentReflected r = separate_incident_reflected(x, z, k);
    EXPECT_NEAR(r.incident, 0.04, 1e-14);
    EXPECT_NEAR(r.reflected, 0.012, 1e-14);
    EXPECT_NEAR(r.coefficient, 0.3, 1e-12);
    EXPECT_LT(r.residual, 1e-15);
    EXPECT_GT(r.conditioning, 0.3);
  }
  EXPECT_THROW(separate_incident_reflected({3.0, 4.0}, {at(3.0), at(4.0)}, k), AnalysisError);
  EXPECT_LT(separate_incident_reflected({3.0, 3.98}, {at(3.0), at(3.98)}, k).conditioning, 0.1);
}

TEST(WaveGauges, DecayPerWavelengthOfAnExponentialAmplitude) {
  const double wavelength = 1.5, lost = 0.02;  // 2 % per wavelength
  std::vector<double> x, a;
  for (double xm : {1.0, 2.5, 4.0, 7.0}) {
    x.push_back(xm);
    a.push_back(0.04 * std::pow(1.0 - lost, xm / wavelength));
  }
  const Decay d = amplitude_decay(x, a, wavelength);
  EXPECT_NEAR(d.per_wavelength, lost, 1e-13);
  EXPECT_NEAR(d.a0, 0.04, 1e-14);
  EXPECT_THROW(amplitude_decay({1.0}, {0.04}, wavelength), AnalysisError);
  EXPECT_THROW(amplitude_decay({1.0, 2.0}, {0.04, 0.0}, wavelength), AnalysisError);
}

// Steady waves reach a gauge after the ramp and the travel at the group velocity (plus settling
// periods), and stay until the run ends or the far wall's reflection returns.
TEST(WaveGauges, TheSteadyWindowStartsAfterTheFrontAndEndsBeforeTheReflection) {
  const auto open = steady_window(4.0, 0.5, 2.4, 2.0, 1.2, 30.0, std::nullopt);
  ASSERT_TRUE(open);
  EXPECT_DOUBLE_EQ(open->t0, 0.5 + 2.4 + 2.0 + 2.4);
  EXPECT_NEAR(open->periods(1.2), 18.0, 1e-9);  // floor((30 - 7.3) / 1.2)
  const auto walled = steady_window(4.0, 0.5, 2.4, 2.0, 1.2, 30.0, 20.0);
  ASSERT_TRUE(walled);
  EXPECT_LE(walled->t1, 0.5 + (40.0 - 4.0) / 2.0 - 1.2);
  EXPECT_GT(walled->t1, 0.5 + (40.0 - 4.0) / 2.0 - 2.4);
  EXPECT_FALSE(steady_window(4.0, 0.5, 2.4, 2.0, 1.2, 8.0, std::nullopt));
}

// A run directory of gauge series: linear waves of the wave maker's target from its start (no ramp),
// with a 10 % reflection from the far end, at five gauges. The analysis finds the target height, the
// period, no phase lag and the reflection, and writes its report.
TEST(WaveFlume, AnalysisOfSyntheticGaugesFindsTheWaveAndItsReflection) {
  Case c;
  c.tank_width = 12.0;
  c.tank_height = 0.8;
  c.gravity = {0.0, -9.81, 0.0};
  Region piston;
  piston.name = "piston";
  piston.max = {0.12, 0.7, 0.0};
  piston.translation.law = MotionLawType::wave;
  piston.translation.height = 0.06;
  piston.translation.period = 1.2;
  piston.translation.depth = 0.4;
  piston.translation.start = 0.5;
  c.walls.push_back(piston);
  const std::vector<double> gauge_x = {1.5, 2.5, 3.0, 3.7, 4.5};
  for (std::size_t m = 0; m < gauge_x.size(); ++m) {
    Probe p;
    p.name = fmt::format("g{}", m + 1);
    p.type = ProbeType::gauge;
    p.point = {gauge_x[m], 0.0, 0.0};
    c.probes.push_back(p);
  }
  c.damping_length = 2.0;  // an absorbing end: the window runs to the end
  c.damping_start = {10.0, 0.0, 0.0};
  const double omega = 2.0 * pi / 1.2, k = waves::wavenumber(omega, 0.4), reflector = 10.0;
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_flume_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "probes");
  for (std::size_t m = 0; m < gauge_x.size(); ++m) {
    const double x = gauge_x[m] - 0.12;
    std::string csv = "time,height\n";
    for (int j = 0; j <= 3000; ++j) {
      const double t = 0.01 * j, tau = t - 0.5;
      double eta = 0.0;
      if (tau > 0.0) eta = 0.03 * std::cos(omega * tau - k * x) + 0.003 * std::cos(omega * tau + k * x - 2.0 * k * reflector);
      csv += fmt::format("{},{}\n", t, 0.4 + eta);
    }
    write_file_atomic(dir / "probes" / (c.probes[m].name + ".csv"), csv);
  }
  const FlumeAnalysis a = analyze_flume(dir, c, {});
  EXPECT_NEAR(a.wave.maker_x, 0.12, 1e-15);
  ASSERT_EQ(a.gauges.size(), 5u);
  for (const auto& g : a.gauges) {
    ASSERT_TRUE(g.harmonics) << g.name << ": " << g.note;
    EXPECT_NEAR(g.zero_crossing->mean_period, 1.2, 1e-3) << g.name;
    // The local amplitude beats between 0.027 and 0.033 with the reflection.
    EXPECT_NEAR(2.0 * g.harmonics->amplitude[0], 0.06, 0.0061) << g.name;
  }
  ASSERT_TRUE(a.reflection);
  EXPECT_NEAR(a.reflection->coefficient, 0.1, 1e-6);
  EXPECT_NEAR(a.reflection->incident, 0.03, 1e-7);
  // The incident wave alone has the target's phase everywhere: its lag is that of the local sum, which
  // the reflection moves by at most asin(0.1) = 5.7 degrees.
  for (const auto& g : a.gauges) {
    const double lag = std::remainder(g.harmonics->phase[0] - g.theory_phase, 2.0 * pi) * 180.0 / pi;
    EXPECT_LT(std::abs(lag), 5.8) << g.name;
  }
  ASSERT_TRUE(a.decay);
  EXPECT_LT(std::abs(a.decay->per_wavelength), 0.1);
  const std::string table = flume_table(a);
  EXPECT_NE(table.find("reflection Kr = 0.100"), std::string::npos) << table;
  write_flume_report(a, dir, dir / "analysis");
  for (const char* f : {"gauges.csv", "summary.csv", "harmonics.svg", "eta_g1.svg", "report.html"})
    EXPECT_TRUE(fs::exists(dir / "analysis" / f)) << f;
  FlumeOptions none;
  Case no_maker = c;
  no_maker.walls.clear();
  EXPECT_THROW(analyze_flume(dir, no_maker, none), AnalysisError);
  none.period = 1.2;
  EXPECT_NO_THROW(analyze_flume(dir, no_maker, none));
  fs::remove_all(dir);
}

// A flap driven by a laboratory record that also holds the gauges' measurements (as the NTNU flume's
// files do): the period, start and ramp are read from the paddle's column, each gauge is compared with
// the column of its name, and the windows close before the beach (a damping zone) can reflect the
// steady waves back. The simulated series are the measured ones 5 % lower and 5 degrees later.
TEST(WaveFlume, ARecordedPaddleIsComparedWithTheMeasurements) {
  const double period = 1.158, omega = 2.0 * pi / period, offset = -10.0, start = 1.0;
  const double k = waves::wavenumber(omega, 1.0), lag = 5.0 * pi / 180.0;
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_recorded_flume_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "probes");
  const std::vector<std::string> names = {"WP_1", "WP_2", "WP_far"};
  const std::vector<double> gauge_x = {3.2, 5.15, 10.5};
  auto paddle = [&](double t) {  // the run's time; a linear ramp over five periods
    const double tau = t - start;
    return tau <= 0.0 ? 0.0 : 0.01 * std::min(1.0, tau / (5.0 * period)) * std::sin(omega * tau);
  };
  auto measured = [&](double t, double x) { return 0.02 * std::cos(omega * t - k * (x - 0.2)); };
  std::string record = "# a synthetic record\nTime [s],WM [m],WP_1 [m],WP_2 [m]\n";
  MotionSeries series;
  for (int j = 0; j <= 4000; ++j) {
    const double t_file = 10.0 + 0.01 * j, t = t_file + offset;
    record += fmt::format("{},{},{},{}\n", t_file, paddle(t), measured(t, 3.2), measured(t, 5.15));
    series.times.push_back(t);
    series.values.push_back(paddle(t) * 38.2);
  }
  write_file_atomic(dir / "record.csv", record);
  for (std::size_t m = 0; m < names.size(); ++m) {
    std::string csv = "time,height\n";
    for (int j = 0; j <= 3000; ++j) {
      const double t = 0.01 * j;
      csv += fmt::format("{},{}\n", t, 1.0 + 0.95 * 0.02 * std::cos(omega * t - k * (gauge_x[m] - 0.2) - lag));
    }
    write_file_atomic(dir / "probes" / (names[m] + ".csv"), csv);
  }
  Case c;
  c.tank_width = 13.83;
  c.tank_height = 1.3;
  c.gravity = {0.0, -9.81, 0.0};
  Region flap;
  flap.name = "flap";
  flap.min = {0.12, 0.1, 0.0};
  flap.max = {0.2, 1.2, 0.0};
  flap.rotation.law = MotionLawType::file;
  flap.rotation.centre = {0.2, 0.1, 0.0};
  flap.rotation.file = (dir / "record.csv").string();
  flap.rotation.time_column = "Time [s]";
  flap.rotation.column = "WM [m]";
  flap.rotation.time_offset = offset;
  flap.rotation.series = std::make_shared<const MotionSeries>(series);
  c.walls.push_back(flap);
  for (std::size_t m = 0; m < names.size(); ++m) {
    Probe p;
    p.name = names[m];
    p.type = ProbeType::gauge;
    p.point = {gauge_x[m], 0.0, 0.0};
    c.probes.push_back(p);
  }
  c.damping_start = {11.1, 0.0, 0.0};
  c.damping_length = 2.73;
  ASSERT_TRUE(has_wave_maker(c));
  const FlumeAnalysis a = analyze_flume(dir, c, {});
  EXPECT_NEAR(a.wave.period, period, 1e-3);
  // The first 2 % excursion of a five-period linear ramp comes 0.14 periods after the start.
  EXPECT_GE(a.wave.start, start);
  EXPECT_LT(a.wave.start, start + 0.2 * period);
  EXPECT_NEAR(a.wave.maker_x, 0.2, 1e-15);
  ASSERT_EQ(a.gauges.size(), 3u);
  for (std::size_t m = 0; m < 2; ++m) {
    const GaugeWaves& g = a.gauges[m];
    ASSERT_TRUE(g.measured_harmonics) << g.name << ": " << g.note;
    // Until the steady waves' reflection from the beach's start (10.9 m from the flap) could return.
    const double back = a.wave.start + a.wave.ramp_time + (2.0 * 10.9 - g.distance) / a.wave.group_velocity;
    EXPECT_LE(g.window->t1, back - period + 1e-9) << g.name;
    EXPECT_GE(g.window->periods(period), 2.0 - 1e-9) << g.name;
    EXPECT_NEAR(g.harmonics->amplitude[0] / g.measured_harmonics->amplitude[0], 0.95, 2e-3) << g.name;
    const double behind = std::remainder(g.harmonics->phase[0] - g.measured_harmonics->phase[0], 2.0 * pi);
    EXPECT_NEAR(behind * 180.0 / pi, 5.0, 0.2) << g.name;
  }
  // 10.3 m from the flap, the steady waves cannot arrive before the beach's reflection of them.
  EXPECT_FALSE(a.gauges[2].window);
  EXPECT_FALSE(a.gauges[2].measured_harmonics);
  const std::string table = flume_table(a);
  EXPECT_NE(table.find("against the measurements"), std::string::npos) << table;
  EXPECT_NE(table.find("-5.0%"), std::string::npos) << table;
  write_flume_report(a, dir, dir / "analysis");
  std::ifstream summary(dir / "analysis" / "summary.csv");
  const std::string text((std::istreambuf_iterator<char>(summary)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("largest first-harmonic error against the measurements,5."), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(dir / "analysis" / "eta_WP_1.svg"));
  fs::remove_all(dir);
}

// The variance spectrum of a sine holds its variance at its frequency.
TEST(IrregularWaves, TheSpectrumOfASineHoldsItsVarianceAtItsFrequency) {
  const Series s = sampled(0.0, 60.0, 0.02, [](double t) { return 0.4 + 0.03 * std::cos(2.0 * pi * 0.8 * t + 0.3); });
  const VarianceSpectrum v = variance_spectrum(s, 0.0, 60.0, 3.0, 1);
  double m0 = 0.0;
  std::size_t peak = 0;
  for (std::size_t k = 0; k < v.f.size(); ++k) {
    m0 += v.s[k] * (v.f[1] - v.f[0]);
    if (v.s[k] > v.s[peak]) peak = k;
  }
  EXPECT_NEAR(v.f[peak], 0.8, 1e-9);
  EXPECT_NEAR(m0, 0.5 * 0.03 * 0.03, 1e-6);
}

// Gauges reading a known JONSWAP sea (the maker's own components, travelling at their wavenumbers)
// give its significant height and peak period.
TEST(IrregularWaves, AKnownSeaGivesItsSignificantHeightAndPeakPeriod) {
  Case c;
  c.tank_width = 12.0;
  c.tank_height = 0.8;
  c.gravity = {0.0, -9.81, 0.0};
  Region piston;
  piston.name = "piston";
  piston.max = {0.12, 0.7, 0.0};
  MotionLawSpec& m = piston.translation;
  m.law = MotionLawType::wave;
  m.spectrum = WaveSpectrum::jonswap;
  m.significant_height = 0.06;
  m.peak_period = 1.2;
  m.depth = 0.4;
  m.components = 50;
  m.ramp = 1.0;
  c.walls.push_back(piston);
  Probe p;
  p.name = "g1";
  p.type = ProbeType::gauge;
  p.point = {2.0, 0.0, 0.0};
  c.probes.push_back(p);
  c.damping_start = {10.0, 0.0, 0.0};
  c.damping_length = 2.0;
  ASSERT_TRUE(has_irregular_maker(c));
  const waves::IrregularSea sea = waves::jonswap_sea(0.06, 1.2, 3.3, 50, 1);
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_irregular_{}", getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "probes");
  std::string csv = "time,height\n";
  for (int j = 0; j <= 2000; ++j) {  // 40 s: the window holds more than the sea's 24 s repeat
    const double t = 0.02 * j;
    double eta = 0.0;
    for (const auto& w : sea.components) {
      const double omega = 2.0 * pi * w.frequency;
      eta += w.amplitude * std::cos(omega * t - waves::wavenumber(omega, 0.4) * 1.88 + w.phase);
    }
    csv += fmt::format("{},{}\n", t, 0.4 + eta);
  }
  write_file_atomic(dir / "probes" / "g1.csv", csv);
  const IrregularAnalysis a = analyze_irregular_flume(dir, c);
  EXPECT_NEAR(a.repeat_period, 24.0, 1e-9);
  ASSERT_EQ(a.gauges.size(), 1u);
  const IrregularGauge& g = a.gauges[0];
  ASSERT_TRUE(g.window) << g.note;
  EXPECT_GT(g.window->periods(1.2), 20.0);
  EXPECT_NEAR(g.hm0 / 0.06, 1.0, 0.05);
  EXPECT_NEAR(g.peak_period / 1.2, 1.0, 0.08);
  const std::string table = irregular_table(a);
  EXPECT_NE(table.find("JONSWAP Hs = 0.06 m"), std::string::npos) << table;
  write_irregular_report(a, dir, dir / "analysis");
  for (const char* f : {"irregular.csv", "spectra.svg", "report.html"})
    EXPECT_TRUE(fs::exists(dir / "analysis" / f)) << f;
  fs::remove_all(dir);
}
