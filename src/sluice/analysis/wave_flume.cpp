#include "sluice/analysis/wave_flume.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sluice/analysis/html_report.hpp"
#include "sluice/analysis/reference_data.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/geometry/wave_theory.hpp"
#include "sluice/io/atomic_file.hpp"

namespace sluice::analysis {

namespace fs = std::filesystem;

namespace {

constexpr double two_pi = 2.0 * std::numbers::pi;

// An angle in (-180, 180] degrees.
double wrapped_degrees(double radians) {
  double d = std::remainder(radians, two_pi) * 180.0 / std::numbers::pi;
  if (d <= -180.0) d += 360.0;
  return d;
}

// The largest x of a wall at rest: a piston's face.
double face_x(const Region& wall) {
  if (wall.shape == Shape::polygon) {
    double x = -1e300;
    for (const auto& p : wall.points) x = std::max(x, p[0]);
    return x;
  }
  return wall.max[0];
}

// The first wall driven by a recorded motion (law = "file"): its index, and which law.
struct RecordedMaker {
  std::size_t wall = 0;
  bool rotation = false;
  const MotionLawSpec* law = nullptr;
};
std::optional<RecordedMaker> recorded_maker(const Case& c) {
  for (std::size_t i = 0; i < c.walls.size(); ++i)
    for (bool rotation : {false, true}) {
      const MotionLawSpec& m = rotation ? c.walls[i].rotation : c.walls[i].translation;
      if (m.law == MotionLawType::file) return RecordedMaker{i, rotation, &m};
    }
  return std::nullopt;
}

// The record as a table: the file on disk, or the record of that name built into the binary.
Table record_table(const MotionLawSpec& m) {
  std::error_code ec;
  if (fs::exists(m.file, ec)) return read_csv_table(m.file);
  return reference_table(m.file);
}

// The record's column holding gauge `name`'s measurement: "name", or "name [unit]".
std::optional<std::size_t> gauge_column(const Table& t, const std::string& name) {
  for (std::size_t k = 0; k < t.columns.size(); ++k)
    if (t.columns[k] == name || t.columns[k].starts_with(name + " [")) return k;
  return std::nullopt;
}

// The start, ramp and (when not given) period of a recorded paddle: it starts when it first moves by
// 2 % of its largest excursion from where it stood, has ramped up when it first reaches 90 % of it,
// and its period is the mean zero-crossing period after that, up to `until`.
void read_record_timing(const MotionSeries& record, double until, FlumeWave& w) {
  Series r{record.times, record.values};
  for (double& y : r.y) y -= record.values.front();
  double peak = 0.0;
  for (double y : r.y) peak = std::max(peak, std::abs(y));
  if (!(peak > 0.0)) throw AnalysisError(fmt::format("the paddle's record {} does not move", w.record));
  std::size_t j = 0;
  while (std::abs(r.y[j]) < 0.02 * peak) ++j;
  w.start = r.t[j];
  while (std::abs(r.y[j]) < 0.9 * peak) ++j;
  w.ramp_time = r.t[j] - w.start;
  if (!(w.period > 0.0)) {
    const double t1 = std::min(until, r.t.back());
    try {
      w.period = zero_crossing_waves(r, r.t[j], t1).mean_period;
    } catch (const AnalysisError& e) {
      throw AnalysisError(fmt::format("the paddle's record {} holds no whole period between t = {:.3g} s (after its "
                                      "ramp) and t = {:.3g} s (the run's end): {}; expected --period",
                                      w.record, r.t[j], t1, e.what()));
    }
  }
}

FlumeWave wave_of(const Case& c, const FlumeOptions& o) {
  FlumeWave w;
  for (std::size_t i = 0; i < c.walls.size() && w.maker.empty(); ++i)
    for (bool rotation : {false, true}) {
      const MotionLawSpec& m = rotation ? c.walls[i].rotation : c.walls[i].translation;
      if (m.law != MotionLawType::wave) continue;
      w.maker = fmt::format("wall[{}].{} ({})", i, rotation ? "rotation" : "translation", c.walls[i].name);
      if (m.spectrum == WaveSpectrum::jonswap) {
        // Irregular waves have no one height and period to measure against: with --period the gauges'
        // harmonics at that period are measured (against --height if given), from the ramp's end.
        if (!(o.period > 0.0))
          throw AnalysisError(fmt::format(
              "{} makes irregular waves (spectrum = \"jonswap\", Hs = {} m, Tp = {} s): their significant height and "
              "peak period are measured by the irregular-wave analysis; the regular one measures them only at one "
              "period given with --period (e.g. --period {}, the peak period)",
              w.maker, m.significant_height, m.peak_period, m.peak_period));
        w.depth = m.depth;
        w.start = m.start;
        w.ramp_time = m.ramp * m.peak_period;
        w.order = 1;
        w.maker_x = rotation ? m.centre[0] : face_x(c.walls[i]);
        break;
      }
      w.height = m.height * m.gain;
      w.period = m.period;
      w.depth = m.depth;
      w.start = m.start;
      w.ramp_time = m.ramp * m.period;
      w.order = rotation ? 1 : m.order;
      w.maker_x = rotation ? m.centre[0] : face_x(c.walls[i]);
      break;
    }
  if (w.maker.empty()) {
    // A paddle driven otherwise (a recorded motion): distances from the first moving wall's face.
    for (const auto& wall : c.walls)
      if (wall.moves()) {
        w.maker_x = wall.rotation.law != MotionLawType::none ? wall.rotation.centre[0] : face_x(wall);
        break;
      }
    if (const auto r = recorded_maker(c)) {
      const Region& wall = c.walls[r->wall];
      w.maker = fmt::format("wall[{}].{} ({}), driven by the record {}", r->wall,
                            r->rotation ? "rotation" : "translation", wall.name, r->law->file);
      w.record = r->law->file;
      w.record_time_offset = r->law->time_offset;
      w.maker_x = r->rotation ? r->law->centre[0] : face_x(wall);
    }
  }
  if (o.period > 0.0) w.period = o.period;
  if (o.height > 0.0) w.height = o.height;
  if (o.depth > 0.0) w.depth = o.depth;
  if (o.maker_x) w.maker_x = *o.maker_x;
  if (!(w.period > 0.0) && w.record.empty())
    throw AnalysisError("the case has no wave maker (a wall with law = \"wave\"); expected the wave's period with "
                        "--period (and --height, --depth to compare with theory)");
  return w;
}

std::string format_window(const std::optional<Window>& w) {
  return w ? fmt::format("{:.2f}-{:.2f}", w->t0, w->t1) : std::string("-");
}

// The first-harmonic height 2 A1 relative to the target, in percent; nan without a target.
double height_error_percent(const FlumeAnalysis& a, const GaugeWaves& g) {
  if (!g.harmonics || !(a.wave.height > 0.0)) return std::nan("");
  return 100.0 * (2.0 * g.harmonics->amplitude[0] / (a.wave.height * g.shoaling) - 1.0);
}

// The first harmonic's amplitude against the measured one, in percent, and how far its phase runs
// behind the measured one, in degrees (positive: the simulated wave arrives later); nan without both.
double measured_error_percent(const GaugeWaves& g) {
  if (!g.harmonics || !g.measured_harmonics) return std::nan("");
  return 100.0 * (g.harmonics->amplitude[0] / g.measured_harmonics->amplitude[0] - 1.0);
}
double measured_phase_lag(const GaugeWaves& g) {
  if (!g.harmonics || !g.measured_harmonics) return std::nan("");
  return wrapped_degrees(g.harmonics->phase[0] - g.measured_harmonics->phase[0]);
}

bool has_measurements(const FlumeAnalysis& a) {
  return std::any_of(a.gauges.begin(), a.gauges.end(), [](const auto& g) { return g.measured_harmonics.has_value(); });
}

std::string num(double v, const char* spec = "{:.4f}") {
  return std::isfinite(v) ? fmt::format(fmt::runtime(spec), v) : std::string("-");
}

}  // namespace

bool has_wave_maker(const Case& c) {
  for (const auto& wall : c.walls)
    if (wall.translation.law == MotionLawType::wave || wall.rotation.law == MotionLawType::wave) return true;
  const auto r = recorded_maker(c);
  if (!r) return false;
  try {
    const Table t = record_table(*r->law);
    for (const auto& p : c.probes)
      if (p.type == ProbeType::gauge && gauge_column(t, p.name)) return true;
  } catch (const AnalysisError&) {
    return false;  // a record that cannot be read holds no measurements to compare with
  }
  return false;
}

FlumeAnalysis analyze_flume(const fs::path& run_dir, const Case& c, const FlumeOptions& options) {
  FlumeAnalysis a;
  a.wave = wave_of(c, options);
  FlumeWave& w = a.wave;
  const double g = std::sqrt(c.gravity[0] * c.gravity[0] + c.gravity[1] * c.gravity[1] + c.gravity[2] * c.gravity[2]);
  std::vector<const Probe*> gauges;
  for (const auto& p : c.probes)
    if (p.type == ProbeType::gauge) gauges.push_back(&p);
  if (gauges.empty())
    throw AnalysisError("the case has no wave gauges ([[probe]] with type = \"gauge\"); expected at least one");

  // The series, and each gauge's still level: its mean before the fastest wave, sqrt(g h), reaches it.
  std::vector<Series> levels;
  for (const Probe* p : gauges) {
    const fs::path file = run_dir / "probes" / (p->name + ".csv");
    std::error_code ec;
    if (!fs::exists(file, ec))
      throw AnalysisError(fmt::format("{}: no such file; expected gauge \"{}\"'s series", file.string(), p->name));
    levels.push_back(read_csv_table(file).series("time", "height"));
    if (levels.back().size() < 2) throw AnalysisError(fmt::format("{}: fewer than two samples", file.string()));
  }
  for (const Series& s : levels) a.end_time = std::max(a.end_time, s.t.back());
  std::optional<Table> record;
  const MotionLawSpec* recorded = w.record.empty() ? nullptr : recorded_maker(c)->law;
  if (recorded) {
    if (!recorded->series) throw AnalysisError(fmt::format("the paddle's record {} was not read with the case", w.record));
    read_record_timing(*recorded->series, a.end_time, w);
    if (options.period > 0.0) w.period = options.period;
    record = record_table(*recorded);
  }
  if (!(w.depth > 0.0)) w.depth = levels.front().y.front();
  w.omega = two_pi / w.period;
  w.k = waves::wavenumber(w.omega, w.depth, g);
  const waves::RegularWave theory = waves::regular_wave(std::max(w.height, 1e-12), w.period, w.depth, g);
  w.wavelength = theory.wavelength;
  w.group_velocity = theory.group_velocity;
  if (w.height > 0.0) {
    const double kh = w.k * w.depth, amplitude = 0.5 * w.height, sh = std::sinh(kh);
    w.bound_second_harmonic =
        0.25 * w.k * amplitude * amplitude * std::cosh(kh) * (2.0 + std::cosh(2.0 * kh)) / (sh * sh * sh);
  }
  a.still_level = w.depth;
  // The far end reflects the waves back unless a damping zone or an absorbing piston takes them.
  const bool absorber = std::any_of(c.walls.begin(), c.walls.end(),
                                    [](const Region& wall) { return wall.translation.law == MotionLawType::absorber; });
  if (!c.damps() && !absorber) a.reflector = c.tank_size()[0] - w.maker_x;

  std::vector<double> decay_x, decay_a;
  for (std::size_t i = 0; i < gauges.size(); ++i) {
    GaugeWaves gw;
    gw.name = gauges[i]->name;
    gw.x = gauges[i]->point[0];
    gw.distance = gw.x - w.maker_x;
    const Series& s = levels[i];
    const double quiet_until = w.start + std::max(0.0, gw.distance) / std::sqrt(g * w.depth);
    const double still = mean_before(s, quiet_until);
    gw.eta = s;
    for (double& y : gw.eta.y) y -= still;
    gw.theory_phase = std::fmod(w.omega * w.start + w.k * gw.distance, two_pi);
    // A gauge standing over another depth than the maker's (by more than 5 %): over a beach.
    gw.depth = still - gauges[i]->point[c.dimension - 1];
    if (w.depth > 0.0 && std::abs(gw.depth - w.depth) > 0.05 * w.depth && gw.depth > 0.0) {
      gw.other_depth = true;
      const double cg = waves::regular_wave(std::max(w.height, 1e-12), w.period, gw.depth, g).group_velocity;
      gw.shoaling = std::sqrt(w.group_velocity / cg);
      gw.theory_phase = std::nan("");
    }
    const bool in_zone = c.damps() && (gw.x - c.damping_start[0]) * c.damping_direction[0] > 0.0;
    gw.window = options.window ? options.window
                               : steady_window(gw.distance, w.start, w.ramp_time, w.group_velocity, w.period,
                                               s.t.back(), a.reflector);
    if (record && c.damps() && !options.window && gw.window) {
      // Before the beach the damping zone stands for reflects the steady waves back to the gauge.
      const double beach = (c.damping_start[0] - w.maker_x) * c.damping_direction[0];
      const double back = w.start + w.ramp_time + (2.0 * beach - gw.distance) / w.group_velocity - w.period;
      const double whole = std::floor((std::min(gw.window->t1, back) - gw.window->t0) / w.period + 1e-9);
      if (whole >= 2.0)
        gw.window->t1 = gw.window->t0 + whole * w.period;
      else
        gw.window.reset();
    }
    if (record) {
      if (const auto col = gauge_column(*record, gw.name)) {
        Series m = record->series(recorded->time_column, record->columns[*col]);
        for (double& t : m.t) t += w.record_time_offset;
        const double still_m = mean_before(m, w.start);
        for (double& y : m.y) y -= still_m;
        gw.measured = std::move(m);
      }
    }
    if (!gw.window) {
      gw.note = record && c.damps() ? "no two steady periods reach it before the beach's reflection returns"
                                    : "no steady waves reach it before the run ends (or before the reflection returns)";
    } else {
      try {
        gw.zero_crossing = zero_crossing_waves(gw.eta, gw.window->t0, gw.window->t1);
        gw.harmonics = fit_harmonics(gw.eta, w.omega, 2, gw.window->t0, gw.window->t1);
        if (gw.measured) gw.measured_harmonics = fit_harmonics(*gw.measured, w.omega, 2, gw.window->t0, gw.window->t1);
      } catch (const AnalysisError& e) {
        gw.note = e.what();
      }
    }
    if (in_zone && gw.note.empty()) gw.note = "in the damping zone";
    if (gw.other_depth && gw.note.empty())
      gw.note = fmt::format("over {:.3g} m of water: against the target shoaled by linear theory, Ks = {:.3f}", gw.depth,
                            gw.shoaling);
    if (gw.harmonics && !in_zone && !gw.other_depth && gw.distance > 0.0) {
      decay_x.push_back(gw.distance);
      decay_a.push_back(gw.harmonics->amplitude[0]);
    }
    a.gauges.push_back(std::move(gw));
  }

  if (decay_x.size() >= 2) a.decay = amplitude_decay(decay_x, decay_a, w.wavelength);

  // Reflection: the gauges outside the zone, their harmonics fitted over one window all share.
  std::optional<Window> common = options.window;
  std::vector<const GaugeWaves*> used;
  for (const auto& gw : a.gauges)
    if (gw.harmonics && gw.distance > 0.0 && gw.note.empty() && !gw.other_depth) used.push_back(&gw);
  if (!common && used.size() >= 2) {
    // From the last gauge's start to the first end (the run's, or a reflection's return), before the
    // windows were cut to whole periods.
    Window cw{-1e300, a.end_time};
    for (const auto* gw : used) {
      cw.t0 = std::max(cw.t0, gw->window->t0);
      if (a.reflector) cw.t1 = std::min(cw.t1, w.start + (2.0 * *a.reflector - gw->distance) / w.group_velocity - w.period);
      if (record && c.damps()) cw.t1 = std::min(cw.t1, gw->window->t1);  // before the beach's reflection
    }
    const double whole = std::floor((cw.t1 - cw.t0) / w.period + 1e-9);
    if (whole >= 2.0) {
      cw.t1 = cw.t0 + whole * w.period;
      common = cw;
    }
  }
  if (used.size() >= 2 && common) {
    std::vector<double> x;
    std::vector<std::complex<double>> z;
    for (const auto* gw : used) {
      x.push_back(gw->distance);
      z.push_back(fit_harmonics(gw->eta, w.omega, 1, common->t0, common->t1).complex(1));
      a.reflection_gauges.push_back(gw->name);
    }
    try {
      const IncidentReflected r = separate_incident_reflected(x, z, w.k);
      // Goda & Suzuki's range for two gauges, 0.05 < spacing / L < 0.45, is a conditioning above 0.158.
      if (r.conditioning >= 0.15) {
        a.reflection = r;
        a.common_window = common;
      } else {
        a.notes.push_back(fmt::format("reflection: not measured: the gauges are too close to a whole number of half "
                                      "wavelengths apart to tell incident from reflected waves (conditioning {:.2f}, "
                                      "expected 0.15 or more); add a gauge a quarter wavelength from the others",
                                      r.conditioning));
      }
    } catch (const AnalysisError& e) {
      a.notes.push_back(e.what());
    }
  } else {
    a.notes.push_back("reflection: fewer than two gauges share two periods of steady waves");
  }
  return a;
}

std::string flume_table(const FlumeAnalysis& a) {
  const FlumeWave& w = a.wave;
  std::string s = fmt::format("wave flume: {}\n", w.maker.empty() ? std::string("wave from the options") : w.maker);
  s += fmt::format("  target     H = {} m, T = {:.4g} s, h = {:.4g} m: L = {:.4g} m, kh = {:.3f}, cg = {:.4g} m/s\n",
                   w.height > 0.0 ? fmt::format("{:.4g}", w.height) : std::string("-"), w.period, w.depth,
                   w.wavelength, w.k * w.depth, w.group_velocity);
  if (w.bound_second_harmonic > 0.0)
    s += fmt::format("  second harmonic bound to the target (Stokes): a2 = {:.5f} m\n", w.bound_second_harmonic);
  s += fmt::format("  {:<10} {:>7} {:>6} {:>13} {:>8} {:>8} {:>8} {:>7} {:>7} {:>8}\n", "gauge", "x (m)", "x/L",
                   "window (s)", "H zc", "T zc", "H1", "H1 err", "phase", "a2");
  for (const auto& g : a.gauges) {
    const double h1 = g.harmonics ? 2.0 * g.harmonics->amplitude[0] : std::nan("");
    const double a2 = g.harmonics ? g.harmonics->amplitude[1] : std::nan("");
    // A recorded paddle's motion is not linear theory's: its phase is compared with the measurement.
    const double phase = g.harmonics && w.record.empty() ? wrapped_degrees(g.harmonics->phase[0] - g.theory_phase)
                                                         : std::nan("");
    s += fmt::format("  {:<10} {:>7.3f} {:>6.2f} {:>13} {:>8} {:>8} {:>8} {:>7} {:>7} {:>8}{}\n", g.name, g.x,
                     g.distance / w.wavelength, format_window(g.window),
                     g.zero_crossing ? num(g.zero_crossing->mean_height) : "-",
                     g.zero_crossing ? num(g.zero_crossing->mean_period) : "-", num(h1),
                     num(height_error_percent(a, g), "{:+.1f}%"), num(phase, "{:+.0f}"), num(a2, "{:.5f}"),
                     g.note.empty() ? "" : "  (" + g.note + ")");
  }
  s += "  (H zc, T zc: mean zero-crossing height and period; H1 = 2 a1 and a2: the first and second harmonics "
       "fitted; H1 err against the target; phase: the first harmonic's lag behind linear theory, degrees)\n";
  if (has_measurements(a)) {
    s += fmt::format("  against the measurements in {} (each gauge's window):\n", a.wave.record);
    s += fmt::format("  {:<10} {:>7} {:>13} {:>9} {:>9} {:>8} {:>9} {:>9} {:>9}\n", "gauge", "x (m)", "window (s)",
                     "a1 sim", "a1 meas", "a1 err", "phase lag", "a2 sim", "a2 meas");
    for (const auto& g : a.gauges) {
      if (!g.measured_harmonics) continue;
      s += fmt::format("  {:<10} {:>7.3f} {:>13} {:>9.5f} {:>9.5f} {:>8} {:>9} {:>9.5f} {:>9.5f}\n", g.name, g.x,
                       format_window(g.window), g.harmonics->amplitude[0], g.measured_harmonics->amplitude[0],
                       num(measured_error_percent(g), "{:+.1f}%"), num(measured_phase_lag(g), "{:+.1f}"),
                       g.harmonics->amplitude[1], g.measured_harmonics->amplitude[1]);
    }
    s += "  (a1, a2: first and second harmonic amplitudes (m), simulated and measured; phase lag: how far the simulated "
         "first harmonic runs behind the measured one, degrees)\n";
  }
  if (a.decay)
    s += fmt::format("  decay      {:.2f} % of the first harmonic per wavelength over {} gauges\n",
                     100.0 * a.decay->per_wavelength, a.decay->gauges);
  if (a.reflection)
    s += fmt::format("  reflection Kr = {:.3f} (incident {:.4g} m, reflected {:.4g} m; gauges {}; window {})\n",
                     a.reflection->coefficient, a.reflection->incident, a.reflection->reflected,
                     fmt::join(a.reflection_gauges, ", "), format_window(a.common_window));
  for (const auto& n : a.notes) s += "  note: " + n + "\n";
  return s;
}

namespace {

std::string gauges_csv(const FlumeAnalysis& a) {
  std::string s =
      "gauge,x,distance,distance_over_wavelength,t0,t1,zero_crossing_height,zero_crossing_period,waves,"
      "first_harmonic_amplitude,first_harmonic_phase,second_harmonic_amplitude,second_harmonic_phase,mean,"
      "target_height,theory_phase,phase_lag_degrees,measured_first_harmonic_amplitude,measured_first_harmonic_phase,"
      "measured_second_harmonic_amplitude,first_harmonic_error_vs_measured_percent,phase_lag_behind_measured_degrees,"
      "still_depth,shoaling_coefficient\n";
  for (const auto& g : a.gauges) {
    auto v = [](bool has, double x) { return has ? fmt::format("{}", x) : std::string(); };
    const bool h = g.harmonics.has_value(), z = g.zero_crossing.has_value(), win = g.window.has_value();
    const bool m = g.measured_harmonics.has_value();
    const bool phased = std::isfinite(g.theory_phase);
    s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", g.name, g.x, g.distance,
                     g.distance / a.wave.wavelength, v(win, win ? g.window->t0 : 0), v(win, win ? g.window->t1 : 0),
                     v(z, z ? g.zero_crossing->mean_height : 0), v(z, z ? g.zero_crossing->mean_period : 0),
                     v(z, z ? static_cast<double>(g.zero_crossing->waves) : 0), v(h, h ? g.harmonics->amplitude[0] : 0),
                     v(h, h ? g.harmonics->phase[0] : 0), v(h, h ? g.harmonics->amplitude[1] : 0),
                     v(h, h ? g.harmonics->phase[1] : 0), v(h, h ? g.harmonics->mean : 0),
                     v(a.wave.height > 0.0, a.wave.height * g.shoaling), v(phased, g.theory_phase),
                     v(h && phased, h ? wrapped_degrees(g.harmonics->phase[0] - g.theory_phase) : 0),
                     v(m, m ? g.measured_harmonics->amplitude[0] : 0), v(m, m ? g.measured_harmonics->phase[0] : 0),
                     v(m, m ? g.measured_harmonics->amplitude[1] : 0), v(m, measured_error_percent(g)),
                     v(m, measured_phase_lag(g)), g.depth, g.shoaling);
  }
  return s;
}

std::string summary_csv(const FlumeAnalysis& a) {
  const FlumeWave& w = a.wave;
  std::string s = "quantity,value,unit\n";
  s += fmt::format("second harmonic bound to the target,{},m\n", w.bound_second_harmonic);
  s += fmt::format("target height,{},m\nperiod,{},s\ndepth,{},m\nwavelength,{},m\nkh,{},\ngroup velocity,{},m/s\n",
                   w.height, w.period, w.depth, w.wavelength, w.k * w.depth, w.group_velocity);
  if (a.decay) s += fmt::format("first-harmonic decay per wavelength,{},\n", a.decay->per_wavelength);
  if (has_measurements(a)) {
    double amplitude = 0.0, phase = 0.0;
    for (const auto& g : a.gauges)
      if (g.measured_harmonics) {
        amplitude = std::max(amplitude, std::abs(measured_error_percent(g)));
        phase = std::max(phase, std::abs(measured_phase_lag(g)));
      }
    s += fmt::format("largest first-harmonic error against the measurements,{},%\n", amplitude);
    s += fmt::format("largest first-harmonic phase difference from the measurements,{},deg\n", phase);
  }
  if (a.reflection)
    s += fmt::format("reflection coefficient,{},\nincident amplitude,{},m\nreflected amplitude,{},m\n",
                     a.reflection->coefficient, a.reflection->incident, a.reflection->reflected);
  return s;
}

}  // namespace

Plot flume_gauge_plot(const FlumeAnalysis& a, const GaugeWaves& g) {
  Plot p;
  p.title = fmt::format("Gauge {} at x = {:.3g} m ({:.2f} wavelengths from the wave maker)", g.name, g.x,
                        g.distance / a.wave.wavelength);
  p.x_label = "t (s)";
  p.y_label = "surface elevation (m)";
  p.series.push_back(curve("sluice", g.eta.t, g.eta.y));
  if (g.measured) {
    // The measurement over the run's time span.
    Series m;
    for (std::size_t j = 0; j < g.measured->size(); ++j)
      if (g.measured->t[j] >= g.eta.t.front() && g.measured->t[j] <= g.eta.t.back()) {
        m.t.push_back(g.measured->t[j]);
        m.y.push_back(g.measured->y[j]);
      }
    if (!m.empty()) p.series.push_back(curve("measured", m.t, m.y));
  }
  if (a.wave.height > 0.0 && g.window && std::isfinite(g.theory_phase)) {
    std::vector<double> t, y;
    for (double s = g.window->t0; s <= g.window->t1 + 1e-9; s += a.wave.period / 40.0) {
      t.push_back(s);
      y.push_back(0.5 * a.wave.height * std::cos(a.wave.omega * s - g.theory_phase));
    }
    PlotSeries th = curve(fmt::format("linear theory, H = {:.3g} m", a.wave.height), t, y);
    th.dashed = true;
    p.series.push_back(th);
  }
  if (g.window) p.bands.push_back({g.window->t0, g.window->t1, "steady window"});
  p.legend = Plot::LegendAt::bottom_left;
  return p;
}

Plot flume_harmonics_plot(const FlumeAnalysis& a) {
  Plot p;
  p.title = "First and second harmonics along the flume";
  p.x_label = "distance from the wave maker (wavelengths)";
  p.y_label = "amplitude (m)";
  // The gauges in order along the flume, whatever their order in the case.
  std::vector<const GaugeWaves*> along;
  for (const auto& g : a.gauges)
    if (g.harmonics) along.push_back(&g);
  std::sort(along.begin(), along.end(), [](const auto* p, const auto* q) { return p->distance < q->distance; });
  std::vector<double> x, a1, a2;
  for (const auto* g : along) {
    x.push_back(g->distance / a.wave.wavelength);
    a1.push_back(g->harmonics->amplitude[0]);
    a2.push_back(g->harmonics->amplitude[1]);
  }
  if (x.empty()) throw AnalysisError("no gauge has steady waves: nothing to plot");
  p.series.push_back(curve("first harmonic a1", x, a1, PlotSeries::Style::line_and_markers));
  p.series.push_back(curve("second harmonic a2", x, a2, PlotSeries::Style::line_and_markers));
  double top = std::max(*std::max_element(a1.begin(), a1.end()), 0.5 * a.wave.height);
  if (a.wave.height > 0.0) {
    PlotSeries target = curve("target H/2", {x.front(), x.back()}, {0.5 * a.wave.height, 0.5 * a.wave.height});
    target.dashed = true;
    p.series.push_back(target);
    PlotSeries bound = curve("Stokes bound a2", {x.front(), x.back()},
                             {a.wave.bound_second_harmonic, a.wave.bound_second_harmonic});
    bound.dashed = true;
    p.series.push_back(bound);
  }
  p.y_range = std::make_pair(0.0, 1.5 * top);  // the legend above the first harmonic
  p.legend = Plot::LegendAt::top_right;
  return p;
}


void write_flume_report(const FlumeAnalysis& a, const fs::path& run_dir, const fs::path& out_dir) {
  create_directories_or_throw(out_dir);
  write_file_atomic(out_dir / "gauges.csv", gauges_csv(a));
  write_file_atomic(out_dir / "summary.csv", summary_csv(a));
  HtmlReport html("Wave flume: " + run_dir.string());
  const FlumeWave& w = a.wave;
  html.heading("The wave");
  html.paragraph(fmt::format("Wave maker: {}. Target: H = {} m, T = {:.4g} s on h = {:.4g} m: wavelength L = {:.4g} m, "
                             "kh = {:.3f}, group velocity {:.4g} m/s; Stokes' second-order bound harmonic a2 = {:.5f} m.",
                             w.maker.empty() ? std::string("given by the options") : w.maker,
                             w.height > 0.0 ? fmt::format("{:.4g}", w.height) : std::string("(none given)"), w.period,
                             w.depth, w.wavelength, w.k * w.depth, w.group_velocity, w.bound_second_harmonic));
  if (a.decay)
    html.paragraph(fmt::format("Decay of the first harmonic: {:.2f} % per wavelength (a1 = A0 exp(-beta x) over {} "
                               "gauges outside the damping zone).",
                               100.0 * a.decay->per_wavelength, a.decay->gauges));
  if (a.reflection)
    html.paragraph(fmt::format("Reflection: Kr = {:.3f} (incident {:.4g} m, reflected {:.4g} m) from gauges {} over "
                               "{} s.",
                               a.reflection->coefficient, a.reflection->incident, a.reflection->reflected,
                               fmt::join(a.reflection_gauges, ", "), format_window(a.common_window)));
  for (const auto& n : a.notes) html.paragraph("Note: " + n);
  if (has_measurements(a)) {
    std::vector<std::vector<std::string>> measured;
    for (const auto& g : a.gauges)
      if (g.measured_harmonics)
        measured.push_back({g.name, fmt::format("{:.3f}", g.x), format_window(g.window),
                            num(g.harmonics->amplitude[0], "{:.5f}"), num(g.measured_harmonics->amplitude[0], "{:.5f}"),
                            num(measured_error_percent(g), "{:+.1f}%"), num(measured_phase_lag(g), "{:+.1f}"),
                            num(g.harmonics->amplitude[1], "{:.5f}"), num(g.measured_harmonics->amplitude[1], "{:.5f}")});
    html.heading("Against the measurements");
    html.paragraph(fmt::format("Each gauge's harmonics fitted over the same window to the simulation and to the column "
                               "of the same name in {} (its still level removed). Phase lag: how far the simulated "
                               "first harmonic runs behind the measured one.",
                               a.wave.record));
    html.table({"gauge", "x (m)", "window (s)", "a1 sluice (m)", "a1 measured (m)", "a1 error", "phase lag (deg)",
                "a2 sluice (m)", "a2 measured (m)"},
               measured);
  }
  std::vector<std::vector<std::string>> rows;
  for (const auto& g : a.gauges) {
    const bool h = g.harmonics.has_value();
    rows.push_back({g.name, fmt::format("{:.3f}", g.x), fmt::format("{:.2f}", g.distance / a.wave.wavelength),
                    format_window(g.window), g.zero_crossing ? num(g.zero_crossing->mean_height) : "-",
                    g.zero_crossing ? num(g.zero_crossing->mean_period) : "-",
                    h ? num(2.0 * g.harmonics->amplitude[0]) : "-", num(height_error_percent(a, g), "{:+.1f}%"),
                    h && w.record.empty() ? num(wrapped_degrees(g.harmonics->phase[0] - g.theory_phase), "{:+.0f}")
                                          : "-",
                    h ? num(g.harmonics->amplitude[1], "{:.5f}") : "-", g.note});
  }
  html.heading("Gauges");
  html.table({"gauge", "x (m)", "x/L", "window (s)", "H zc (m)", "T zc (s)", "H1 (m)", "H1 err", "phase lag (deg)",
              "a2 (m)", "note"},
             rows);
  if (std::any_of(a.gauges.begin(), a.gauges.end(), [](const auto& g) { return g.harmonics.has_value(); })) {
    const std::string svg = svg_plot(flume_harmonics_plot(a));
    write_file_atomic(out_dir / "harmonics.svg", svg);
    html.figure(svg, "The first and second harmonics' amplitudes at each gauge with steady waves.");
  }
  for (const auto& g : a.gauges) {
    const std::string svg = svg_plot(flume_gauge_plot(a, g));
    write_file_atomic(out_dir / ("eta_" + g.name + ".svg"), svg);
    html.figure(svg, fmt::format("Gauge {}: the surface elevation, {} over the steady window.", g.name,
                                 g.measured ? "with the measurement" : "with linear theory"));
  }
  write_file_atomic(out_dir / "report.html", html.html());
}

}  // namespace sluice::analysis
