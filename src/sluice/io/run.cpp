#include "sluice/io/run.hpp"

#include <fmt/format.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <tuple>

#include "sluice/case/case_error.hpp"
#include "sluice/case/params.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/io/append_file.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/directory_lock.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/bodies.hpp"
#include "sluice/io/probes.hpp"
#include "sluice/physics/simd_target.hpp"

namespace sluice {

namespace {

using steady = std::chrono::steady_clock;

double seconds_since(steady::time_point t0) {
  return std::chrono::duration<double>(steady::now() - t0).count();
}

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

// Index of the first frame time k * interval strictly after t (frames land exactly on those times,
// computed as static_cast<double>(k) * interval). Exact, so that a restart finds the same next frame
// and checkpoint times as the run that never stopped.
std::int64_t next_index_after(double t, double interval) {
  auto k = static_cast<std::int64_t>(std::floor(t / interval)) + 1;
  while (k > 0 && static_cast<double>(k - 1) * interval > t) --k;
  while (static_cast<double>(k) * interval <= t) ++k;
  return k;
}

// The time a run stops at. Frame and checkpoint times are computed as k * interval, which can differ
// from the decimal a user writes by rounding (3 * 0.1 = 0.30000000000000004): an end time within
// rounding of one of them is taken as that time, so that a run with `time.end = 0.3` stops exactly
// where a longer run of the same case writes its frame, and a restart from its checkpoint continues
// that longer run bit for bit.
double stop_time(const Case& c) {
  for (const double interval : {c.output_interval, c.checkpoint_interval}) {
    if (!(interval > 0.0)) continue;
    const double k = std::round(c.end_time / interval);
    const double on_grid = k * interval;
    if (std::abs(on_grid - c.end_time) <= 1e-9 * interval) return on_grid;
  }
  return c.end_time;
}

// Output files are written by the root process alone. `write` runs there; with several processes, an
// error there is sent to every process, and each throws it, so that all stop together (the others
// would otherwise wait for the root at the next step).
template <class F>
void on_root(const Communicator* comm, F&& write) {
  if (comm == nullptr) {
    write();
    return;
  }
  std::string error;
  if (comm->is_root()) {
    try {
      write();
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "an output could not be written";
    }
  }
  error = comm->broadcast(error);
  if (!error.empty()) throw IoError(error);
}

void remove_previous_outputs(const std::filesystem::path& dir, const std::string& case_name) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (const char* name : {output_files::diagnostics, output_files::checkpoint, output_files::summary})
    fs::remove(dir / name, ec);
  fs::remove(dir / (case_name + ".pvd"), ec);
  for (const char* sub : {output_files::frames_dir, output_files::probes_dir, output_files::bodies_dir}) {
    if (!fs::is_directory(dir / sub, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir / sub, ec)) {
      const auto ext = entry.path().extension();
      if (ext == ".npz" || ext == ".vtu" || ext == ".csv") fs::remove(entry.path(), ec);
    }
  }
}

// Each frame's files (.npz, .vtu) are written whole; diagnostics rows, .pvd entries and probe samples
// are appended to their files, so a frame costs the same at any point of a run.
class Outputs {
 public:
  Outputs(const Simulation& sim, std::filesystem::path dir, bool fresh, double wall_before, const Communicator* comm)
      : dir_(std::move(dir)), interval_(sim.config().output_interval), wall_before_(wall_before),
        write_npz_(sim.config().writes("npz")), write_vtk_(sim.config().writes("vtk")), comm_(comm),
        root_(sim.is_root()), diagnostics_(dir_ / output_files::diagnostics, diagnostics_header),
        pvd_(dir_ / (sim.config().name + ".pvd"), pvd_header(), pvd_footer()),
        probes_(sim.config().probes, sim.dimension(), dir_ / output_files::probes_dir, sim.time(), fresh, root_),
        bodies_(sim, dir_ / output_files::bodies_dir, sim.config().bodies_interval, sim.time(), fresh, root_) {
    on_root(comm_, [&] {
      create_directories_or_throw(dir_ / output_files::frames_dir);
      if (!fresh) keep_until_checkpoint(sim.time());
    });
  }

  template <class Write>
  static void write_streamed(const std::filesystem::path& path, Write&& write) {
    AtomicFile file(path);
    write([&](std::string_view bytes) { file.write(bytes); });
    file.commit();
  }

  static std::string frame_stem(std::int64_t index) {
    return fmt::format("{}/frame_{:06}", output_files::frames_dir, index);
  }

  void write_frame(std::int64_t index, const Simulation& sim, double wall_seconds) {
    const Frame frame = make_frame(sim);  // collective: every process's particles, on the root
    const Diagnostics diagnostics = sim.diagnostics();
    on_root(comm_, [&] {
      const std::string stem = frame_stem(index);
      // Streamed into the files: a frame's bytes are never all in memory at once.
      if (write_npz_) write_streamed(dir_ / (stem + ".npz"), [&](const ByteSink& out) { write_frame_npz(frame, out); });
      if (write_vtk_) {
        write_streamed(dir_ / (stem + ".vtu"), [&](const ByteSink& out) { write_frame_vtu(frame, out); });
        pvd_.append(pvd_entry(frame.time, stem + ".vtu"));
      }
      diagnostics_.append(diagnostics_row(diagnostics, wall_before_ + wall_seconds));
      probes_.flush();
      bodies_.flush();
    });
    ++frames_written_;
  }

  void sample_probes(const Simulation& sim) {
    probes_.sample(sim);
    bodies_.sample(sim);
  }

  void write_checkpoint_file(const Simulation& sim, double wall_seconds) {
    // What a restart keeps (probe samples, diagnostics rows and .pvd entries up to the checkpoint) is
    // on disk, durably, before the checkpoint is. The checkpoint is streamed into its file (collective:
    // every process's particles, on the root); a write error on the root is held until every process
    // is through, then thrown on all of them.
    std::optional<AtomicFile> file;
    on_root(comm_, [&] {
      probes_.flush();
      probes_.sync();
      bodies_.flush();
      bodies_.sync();
      diagnostics_.sync();
      pvd_.sync();
      file.emplace(dir_ / output_files::checkpoint);
    });
    std::string failed;
    write_checkpoint_bytes(sim, wall_before_ + wall_seconds, [&](std::string_view bytes) {
      if (!failed.empty()) return;
      try {
        file->write(bytes);
      } catch (const std::exception& e) {
        failed = e.what();
      }
    });
    on_root(comm_, [&] {
      if (!failed.empty()) throw IoError(failed);
      file->commit();
    });
  }

  [[nodiscard]] int frames_written() const { return frames_written_; }

 private:
  static constexpr const char* diagnostics_header =
      "time,step,dt,max_speed,min_density,max_density,kinetic_energy,potential_energy,total_energy,total_mass,"
      "leaks,outflow,min_particle_distance,wall_time\n";

  static std::string diagnostics_row(const Diagnostics& d, double wall_seconds) {
    return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3f}\n", d.time, d.step, d.dt, d.max_speed,
                       d.min_density, d.max_density, d.kinetic_energy, d.potential_energy,
                       d.kinetic_energy + d.potential_energy, d.total_mass, d.leaks, d.outflow,
                       d.min_particle_distance, wall_seconds);
  }

  // Frames 0..K at the regular times up to the checkpoint were written before it and are kept, with
  // their diagnostics rows and .pvd entries. A frame written at the checkpoint time when that was not a
  // regular frame time (the end of the previous run, or Ctrl-C) is dropped: the continued run writes
  // that frame number at its regular time, as the run that never stopped did.
  void keep_until_checkpoint(double checkpoint_time) {
    const std::int64_t last = next_index_after(checkpoint_time, interval_) - 1;
    std::error_code ec;
    const auto diagnostics = dir_ / output_files::diagnostics;
    if (std::filesystem::exists(diagnostics, ec))
      diagnostics_.resume(csv_rows_until(read_file(diagnostics), static_cast<double>(last) * interval_));
    if (!write_vtk_) return;
    // Rebuilt from the frames on disk rather than cut: that also mends an entry cut off by a kill.
    std::vector<std::pair<double, std::string>> entries;
    for (std::int64_t k = 0; k <= last; ++k)
      if (std::filesystem::exists(dir_ / (frame_stem(k) + ".vtu"), ec))
        entries.emplace_back(static_cast<double>(k) * interval_, frame_stem(k) + ".vtu");
    pvd_.resume(entries.empty() ? std::string() : pvd_text(entries));
  }

  std::filesystem::path dir_;
  double interval_;
  double wall_before_;
  bool write_npz_;
  bool write_vtk_;
  const Communicator* comm_;
  bool root_;
  AppendFile diagnostics_;
  AppendFile pvd_;
  ProbeRecorder probes_;
  BodyRecorder bodies_;
  int frames_written_ = 0;
};

class Progress {
 public:
  Progress(RunOptions::Progress mode, std::ostream& log, double t_start, double t_end, std::size_t particles)
      : mode_(mode), log_(log), t_start_(t_start), t_end_(t_end), particles_(particles) {}

  void update(const Simulation& sim, std::int64_t steps, double wall, bool force = false) {
    if (mode_ == RunOptions::Progress::none) return;
    const double t = sim.time();
    if (mode_ == RunOptions::Progress::tty) {
      if (!force && wall - last_wall_ < 0.2) return;
    } else {
      const double every = 0.05 * (t_end_ - t_start_);
      if (!force && t < next_line_t_ && wall - last_wall_ < 30.0) return;
      next_line_t_ = t + every;
    }
    last_wall_ = wall;
    const double rate = wall > 0 ? static_cast<double>(particles_) * static_cast<double>(steps) / wall : 0.0;
    const double eta = t > t_start_ ? wall * (t_end_ - t) / (t - t_start_) : NAN;
    const std::string line =
        fmt::format("t = {:.3f}/{:.3f} s  step {}  dt {:.2e} s  {:.2f} M particle-steps/s  ETA {}", t, t_end_,
                    sim.clock().step, sim.clock().last_dt, rate * 1e-6, format_duration(eta));
    if (mode_ == RunOptions::Progress::tty) log_ << "\r" << line << "\x1b[K" << std::flush;
    else log_ << line << "\n" << std::flush;
  }

  void finish() {
    if (mode_ == RunOptions::Progress::tty) log_ << "\n";
  }

 private:
  RunOptions::Progress mode_;
  std::ostream& log_;
  double t_start_, t_end_;
  std::size_t particles_;
  double last_wall_ = -1e9;
  double next_line_t_ = -1e300;
};

// A moving wall outside the tank, and "N particles are bad; the first:" with a line for each offender
// the check described.
std::string describe_offenders(const Health& health) {
  std::string m = health.wall_outside.empty() ? "" : health.wall_outside + "\n";
  if (health.offending == 0) return m;
  m += fmt::format("{} particle{} bad; the first:\n", health.offending, health.offending == 1 ? " is" : "s are");
  auto vector = [](const Vec3& v, int dimension) {
    std::string s = fmt::format("({:.4g}", v[0]);
    for (int d = 1; d < dimension; ++d) s += fmt::format(", {:.4g}", v[d]);
    return s + ")";
  };
  for (const Offender& o : health.first)
    m += fmt::format("  id {} at {} m, velocity {} m/s, density {:.6g} kg/m^3, {} neighbours: {}\n", o.id,
                     vector(o.position, o.dimension), vector(o.velocity, o.dimension), o.density, o.neighbours,
                     o.reason);
  return m;
}

std::string describe_instability(const std::string& failure, const Health& health, double time, std::int64_t step,
                                 const Simulation& good, std::int64_t frame, const std::filesystem::path& dir) {
  if (failure.empty() && health.offending == 0 && !health.wall_outside.empty())
    return fmt::format("the run stopped at t = {:.6g} s (step {}): {}: a moving wall must stay inside the tank until "
                       "time.end = {:.6g} s.\nThe last good state (t = {:.6g} s, step {}) is saved as {}/frame_{:06} and "
                       "{} in {}.",
                       time, step, health.wall_outside, good.config().end_time, good.time(), good.clock().step,
                       output_files::frames_dir, frame, output_files::checkpoint, dir.string());
  std::string m = fmt::format("the run became unstable at t = {:.6g} s (step {}): ", time, step);
  m += failure.empty() ? describe_offenders(health) : failure + "\n";
  m += fmt::format("The last good state (t = {:.6g} s, step {}) is saved as {}/frame_{:06} and {} in {}.\n",
                   good.time(), good.clock().step, output_files::frames_dir, frame, output_files::checkpoint,
                   dir.string());
  m += "Usual causes: a time step above the stability limit (time.dt; keep time.dt = 0 for the adaptive step, "
       "or lower time.cfl), too little damping (physics.artificial_viscosity), or a sound speed "
       "(fluid.sound_speed) too low for the flow speeds.";
  return m;
}

// A restart's --set assignments to the case stored in its checkpoint: only time.end may change.
void apply_restart_overrides(Case& stored, const std::vector<std::string>& assignments, const std::string& source) {
  for (const std::string& assignment : assignments) {
    const std::string key = assignment.substr(0, assignment.find('='));
    const auto first = key.find_first_not_of(" \t");
    const auto last = key.find_last_not_of(" \t");
    if (first == std::string::npos || key.substr(first, last - first + 1) != "time.end")
      throw CaseError(fmt::format(
          "--set {}: a restart continues the case stored in {}; only time.end can be changed (to run on past "
          "its end)",
          assignment, source));
    apply_override(stored, assignment);
  }
}

// Where a run starts: a case at t = 0, or the state in a checkpoint.
struct Start {
  std::unique_ptr<Simulation> sim;
  double wall_before = 0.0;  // wall time of the runs before a restart
};

// Every process reads the checkpoint and keeps its region's particles (Solver).
Start start_from_checkpoint(const RunOptions& options) {
  const std::string source = options.restart->string();
  Checkpoint cp = read_checkpoint(*options.restart);
  apply_restart_overrides(cp.config, options.restart_overrides, source);
  if (cp.clock.time >= stop_time(cp.config))
    throw CaseError(fmt::format(
        "{}: the checkpoint is at t = {} s, already at the case's end (time.end = {} s); to run on, give a later "
        "end: sluice run --restart {} --set time.end=<seconds>",
        source, cp.clock.time, cp.config.end_time, source));
  try {
    return {std::make_unique<Simulation>(cp.config, std::move(cp.particles), cp.clock, options.threads, options.comm),
            cp.wall_seconds};
  } catch (const CaseError& e) {
    throw CaseError(fmt::format("{}: not a usable checkpoint: {}", source, e.what()));
  }
}

// The state a run starts from passes the instability guard, or the run does not start: a case whose
// set-up is already unusable (water at an absurd hydrostatic density), or a checkpoint whose values
// are not a state a run can reach (a crafted file whose checksum passes), is refused before anything
// is written. Collective.
void check_start(const Simulation& sim, const RunOptions& options) {
  const Health health = sim.check_health();
  if (health.ok()) return;
  if (options.restart) {
    std::string offenders = describe_offenders(health);
    offenders.pop_back();  // its last line's newline
    throw CaseError(fmt::format("{}: not a usable checkpoint: {}", options.restart->string(), offenders));
  }
  throw CaseError(fmt::format(
      "the case's initial state is unusable: {}Usual causes: a sound speed (fluid.sound_speed) too low for the "
      "water's depth under the hydrostatic start (physics.hydrostatic_start), or an initial pressure "
      "(physics.initial_pressure) beyond what the equation of state allows.",
      describe_offenders(health)));
}

// The frames a run from its current time to its end writes: one at each output interval, and the last.
double planned_frames(const Simulation& sim) {
  const Case& c = sim.config();
  return std::floor(std::max(0.0, stop_time(c) - sim.time()) / c.output_interval) + 1.0;
}

// What a run will write, checked before it starts. Steps land on the frame and checkpoint times, so
// an interval shorter than the longest step the case can take (time.cfl h / c0, or time.dt: the
// adaptive step never exceeds it, as the sound speed is at least c0) would cut every step to that
// interval and write a frame at each: refused, as are more frames than output.max_frames. Every
// process decides alike, from the case.
void check_output_plan(const Simulation& sim) {
  const Case& c = sim.config();
  const double longest_step = c.fixed_dt > 0.0 ? c.fixed_dt : c.cfl * c.smoothing_length() / c.sound_speed;
  const std::string step_is = c.fixed_dt > 0.0 ? fmt::format("time.dt = {:.3g} s", longest_step)
                                               : fmt::format("up to time.cfl h / c0 = {:.3g} s", longest_step);
  for (const auto& [key, interval] : {std::pair{"output.interval", c.output_interval},
                                      std::pair{"output.checkpoint_interval", c.checkpoint_interval}})
    if (interval > 0.0 && interval < longest_step)
      throw CaseError(fmt::format(
          "{} = {:.3g} s is shorter than the time step ({}): every step would be cut to {:.3g} s to land on "
          "it; expected {} >= {:.3g} s (a step's length)",
          key, interval, step_is, interval, key, longest_step));
  const double frames = planned_frames(sim);
  if (frames > static_cast<double>(c.max_frames))
    throw CaseError(fmt::format(
        "the run would write {:.0f} frames (time.end = {} s every output.interval = {} s), more than "
        "output.max_frames = {}; expected a longer output.interval, or a larger output.max_frames to write that "
        "many",
        frames, c.end_time, c.output_interval, c.max_frames));
}

// At most how many particles the set-up of `c` makes: the lattice points of the water regions' and the
// wall regions' bounding boxes, and of the tank's walls (a shell wall_layers spacings thick).
double particles_at_most(const Case& c) {
  const int dim = c.dimension;
  auto points_in = [&](const Vec3& lo, const Vec3& hi) {
    double n = 1.0;
    for (int d = 0; d < dim; ++d) n *= std::max(0.0, hi[d] - lo[d]) / c.dx + 1.0;
    return n;
  };
  auto bounds = [&](const Region& r) -> std::pair<Vec3, Vec3> {
    if (r.shape == Shape::mesh && r.mesh) return {r.mesh->lower(), r.mesh->upper()};
    if (r.shape == Shape::polygon && !r.points.empty()) {
      Vec3 lo{r.points[0][0], r.points[0][1], 0.0}, hi = lo;
      for (const Vec2& q : r.points)
        for (int d = 0; d < 2; ++d) {
          lo[d] = std::min(lo[d], q[d]);
          hi[d] = std::max(hi[d], q[d]);
        }
      return {lo, hi};
    }
    return {r.min, r.max};
  };
  double n = 0.0;
  for (const Region& r : c.water) n += std::apply(points_in, bounds(r));
  for (const Region& r : c.walls) n += std::apply(points_in, bounds(r));
  const double shell = wall_layers(c) * c.dx;
  const Vec3 size = c.tank_size();
  Vec3 lo{}, hi{};
  for (int d = 0; d < dim; ++d) {
    lo[d] = -shell;
    hi[d] = size[d] + shell;
  }
  n += points_in(lo, hi) - points_in(Vec3{}, size);
  return n;
}

// The memory this process may use: what the kernel reports available (MemAvailable), or the process's
// address-space limit if lower; 0 if neither is known.
double memory_available() {
  double bytes = 0.0;
  if (std::FILE* f = std::fopen("/proc/meminfo", "r")) {
    char line[256];
    while (std::fgets(line, sizeof line, f) != nullptr) {
      unsigned long long kb = 0;
      if (std::sscanf(line, "MemAvailable: %llu kB", &kb) == 1) bytes = static_cast<double>(kb) * 1024.0;
    }
    std::fclose(f);
  }
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const auto as = static_cast<double>(limit.rlim_cur);
    bytes = bytes > 0.0 ? std::min(bytes, as) : as;
  }
  return bytes;
}

// A case whose particles would not fit in memory is refused before the set-up allocates them (which
// would end in the out-of-memory killer, or minutes of swapping): each particle takes about 400 bytes
// in 2D and 500 in 3D while the run steps (measured on the default cases; its fields, the neighbour
// grid, the step-start state). Every process builds the whole set-up before keeping its share, so
// the least memory of any process decides, for all of them alike (collective).
void check_memory(const Case& c, const Communicator* comm) {
  double available = memory_available();
  if (!(available > 0.0)) available = std::numeric_limits<double>::infinity();
  if (comm != nullptr) available = comm->reducer().min(available);
  if (!std::isfinite(available)) return;
  const double particles = particles_at_most(c);
  const double need = particles * (c.dimension == 3 ? 500.0 : 400.0);
  if (need <= available) return;
  throw CaseError(fmt::format(
      "domain.dx = {} m makes up to {:.3g} particles, which need about {:.3g} GB of memory; {} {:.3g} GB "
      "available; expected a larger domain.dx (memory goes as dx^-{})",
      c.dx, particles, need * 1e-9, comm != nullptr && comm->size() > 1 ? "a process has only" : "this process has",
      available * 1e-9, c.dimension));
}

// The bytes of the frames a run plans to write: the .npz holds x, v (Dim components each), rho and p as
// doubles, kind (1 byte) and id (4) per particle; the .vtu the same with 3 components for x and v, and
// its cells (about 90 bytes a particle).
double planned_frame_bytes(const Simulation& sim) {
  const Case& c = sim.config();
  const double dim = c.dimension;
  const double per_particle = (c.writes("npz") ? 8.0 * (2.0 * dim + 2.0) + 5.0 : 0.0) + (c.writes("vtk") ? 90.0 : 0.0);
  return planned_frames(sim) * per_particle * static_cast<double>(sim.particle_count());
}

// The output directory (existing) has room for the frames planned, or the run does not start.
void check_room(const std::filesystem::path& dir, double bytes, const Simulation& sim) {
  std::error_code ec;
  const std::filesystem::space_info space = std::filesystem::space(dir, ec);
  if (ec || space.capacity == 0 || bytes <= static_cast<double>(space.available)) return;  // (/proc: no size)
  throw IoError(fmt::format(
      "{}: the run would write about {:.3g} GB of frames ({:.0f} frames of {} particles), and {} has {:.3g} GB "
      "free; expected a longer output.interval, fewer output.formats, or more room",
      dir.string(), bytes * 1e-9, planned_frames(sim),
      sim.particle_count(), dir.parent_path().string(), static_cast<double>(space.available) * 1e-9));
}

void prepare_output_dir(const std::filesystem::path& dir, const std::string& case_name, bool fresh) {
  create_directories_or_throw(dir);
  for (const char* sub : {".", output_files::frames_dir, output_files::probes_dir, output_files::bodies_dir})
    remove_stale_temp_files(dir / sub);
  if (fresh) remove_previous_outputs(dir, case_name);
}

// The next frame and checkpoint, as indices k of the times k * interval, and the time the run stops at.
class Schedule {
 public:
  Schedule(const Case& c, double t)
      : frame_interval_(c.output_interval), checkpoint_interval_(c.checkpoint_interval), end_(stop_time(c)),
        next_frame_(next_index_after(t, frame_interval_)),
        next_checkpoint_(checkpoint_interval_ > 0 ? next_index_after(t, checkpoint_interval_) : 0) {}

  [[nodiscard]] double end() const { return end_; }
  [[nodiscard]] std::int64_t next_frame() const { return next_frame_; }

  // The time the next step must end on if it would pass it: the next frame, checkpoint or the end.
  [[nodiscard]] double step_limit() const {
    const double limit = std::min(frame_time(), end_);
    return checkpoint_interval_ > 0 ? std::min(limit, checkpoint_time()) : limit;
  }

  // A frame is due at its time, and at the end (which may fall between frame times).
  [[nodiscard]] bool frame_due(double t) const { return t >= frame_time() || t >= end_; }
  void frame_written(double t) {
    if (t >= frame_time()) ++next_frame_;
  }

  [[nodiscard]] bool checkpoint_due(double t) const { return checkpoint_interval_ > 0 && t >= checkpoint_time(); }
  void checkpoint_written(double t) { next_checkpoint_ = next_index_after(t, checkpoint_interval_); }

 private:
  [[nodiscard]] double frame_time() const { return static_cast<double>(next_frame_) * frame_interval_; }
  [[nodiscard]] double checkpoint_time() const {
    return static_cast<double>(next_checkpoint_) * checkpoint_interval_;
  }

  double frame_interval_;
  double checkpoint_interval_;
  double end_;
  std::int64_t next_frame_;
  std::int64_t next_checkpoint_;
};

// A run from its start to its end (or Ctrl-C): the steps, and the outputs due after each.
class Run {
 public:
  Run(Start start, const RunOptions& options, std::ostream& log, steady::time_point wall_start)
      : options_(options), wall_start_(wall_start), fresh_(!options.restart), sim_(std::move(start.sim)),
        outputs_(*sim_, options.output_dir, fresh_, start.wall_before, options.comm),
        schedule_(sim_->config(), sim_->time()),
        progress_(sim_->is_root() ? options.progress : RunOptions::Progress::none, log, sim_->time(), schedule_.end(),
                  sim_->particle_count()) {
    // The set-up's notes now, before a long run, and again in the summary.
    if (sim_->is_root() && options.progress != RunOptions::Progress::none) {
      for (const std::string& n : sim_->setup_notes()) log << "sluice: note: " << n << "\n";
      if (checkpoint_wall_interval_ > 0.0)
        log << fmt::format("sluice: a checkpoint every {:g} s of wall time (output.checkpoint_wall_interval) into {}; "
                           "after a kill, `sluice run --restart {}` continues from it\n",
                           checkpoint_wall_interval_, (options.output_dir / output_files::checkpoint).string(),
                           (options.output_dir / output_files::checkpoint).string());
    }
  }

  RunResult to_end() {
    sim_->visit([&](const auto& solver) {
      if (const auto* d = solver.distribution()) {
        bytes_before_ = d->bytes_sent();
        exchange_seconds_before_ = d->exchange_seconds();
      }
    });
    try {
      if (fresh_) {
        outputs_.sample_probes(*sim_);
        outputs_.write_frame(0, *sim_, 0.0);
      }
      loop_start_ = steady::now();
      last_checkpoint_ = loop_start_;
      while (sim_->time() < schedule_.end()) {
        const Request request = requested();
        if (request == Request::stop) {
          interrupted_ = true;
          break;
        }
        if (request == Request::checkpoint) write_checkpoint();
        step();
        write_due_outputs();
        progress_.update(*sim_, steps_, seconds_since(loop_start_));
      }
      progress_.update(*sim_, steps_, seconds_since(loop_start_), true);
      progress_.finish();
      return finish();
    } catch (const ProcessFailure& e) {
      stop_failed(e.failure());  // another process failed: this one learnt of it in a collective call
    } catch (const std::exception& e) {
      // An error every process met alike is reported as it is. With one process, so is an error
      // outside a step (writing the outputs): there is no other state to save than the one that failed.
      if (fails_alike(e) || (options_.comm == nullptr && !mid_step_)) throw;
      const int kind = dynamic_cast<const std::runtime_error*>(&e) != nullptr ? kUnstable : kFailed;
      const std::string what = error_text(e);
      stop_failed(options_.comm != nullptr ? options_.comm->fail(what, kind) : Failure{0, 1, kind, what});
    }
  }

 private:
  [[nodiscard]] double wall() const { return seconds_since(wall_start_); }

  // What a step's end asks for, on any process, so that every process does it after the same step:
  // a stop (Ctrl-C, SIGTERM, SIGHUP), which writes a checkpoint, or a checkpoint because
  // output.checkpoint_wall_interval seconds of wall time have passed since the last (one reduction
  // for both).
  enum class Request { none = 0, checkpoint = 1, stop = 2 };
  [[nodiscard]] Request requested() const {
    Request here = Request::none;
    if (options_.stop_requested != nullptr && options_.stop_requested->load()) here = Request::stop;
    else if (checkpoint_wall_interval_ > 0.0 && seconds_since(last_checkpoint_) >= checkpoint_wall_interval_)
      here = Request::checkpoint;
    if (options_.comm == nullptr) return here;
    return static_cast<Request>(std::lround(options_.comm->reducer().max(static_cast<double>(here))));
  }

  // Writes a checkpoint now (the state at the end of the last step), and times it: the interval
  // between the periodic ones is stretched to 50 times that, so that they cost at most 2 % of the run.
  void write_checkpoint() {
    const auto start = steady::now();
    outputs_.write_checkpoint_file(*sim_, wall());
    last_checkpoint_ = steady::now();
    const double seconds = seconds_since(start);
    if (checkpoint_wall_interval_ > 0.0)
      checkpoint_wall_interval_ = std::max(sim_->config().checkpoint_wall_interval, 50.0 * seconds);
  }

  // The instability guard: if the step leaves any particle non-finite, far outside the tank or at an
  // absurd density, go back to the state before it, save that and stop. (A step that throws, which
  // the solver does when the time step is not finite, is stopped the same way: to_end, stop_failed.)
  void step() {
    mid_step_ = true;
    sim_->step(schedule_.step_limit());
    mid_step_ = false;
    const Health health = sim_->check_health();
    if (!health.ok()) {
      const double bad_time = sim_->time();
      const std::int64_t bad_step = sim_->clock().step;
      sim_->restore_saved_state();
      save_last_good_state();
      throw InstabilityError(describe_instability("", health, bad_time, bad_step, *sim_, schedule_.next_frame(),
                                                  options_.output_dir));
    }
    ++steps_;
    particle_steps_ += static_cast<double>(particles_);
    if (sim_->clock().outflow != outflow_) {  // the same on every process: a collective call or none
      outflow_ = sim_->clock().outflow;
      particles_ = sim_->particle_count();
    }
    frame_is_current_ = false;
    outputs_.sample_probes(*sim_);
  }

  // How a process's error is classed for the others (Failure::kind): a std::runtime_error from a
  // step is the solver finding the run unstable (a time step that is not finite); anything else
  // (out of memory, a broken invariant) is a failure of the process.
  static constexpr int kFailed = 0, kUnstable = 1;

  // After an error on any process, every process here together (after fail(), or the ProcessFailure
  // that it raised in the others): back to the state before the step the error cut short, that state
  // saved as the last frame and a checkpoint, and one error for all. A step is cut short on all
  // processes if on any (the others wait in its collective calls, or have finished it; a finished
  // step's start is still saved). The state is saved only if it is whole: every process back at the
  // start of the step, and every particle there once (an error in the middle of moving particles
  // between processes can lose some); otherwise the last checkpoint is what remains.
  [[noreturn]] void stop_failed(const Failure& f) {
    const Reducer& all = options_.comm != nullptr ? options_.comm->reducer() : serial_reducer();
    const double bad_time = sim_->time();
    const std::int64_t bad_step = sim_->clock().step;
    bool whole = true;
    if (all.max(mid_step_ ? 1.0 : 0.0) > 0.0) {
      const double saved = sim_->has_saved_state() ? 1.0 : 0.0;
      whole = all.min(saved) == all.max(saved);
      sim_->restore_saved_state();
      mid_step_ = false;
    }
    whole = whole && sim_->particle_count() == particles_;
    const std::string at = fmt::format("at t = {:.6g} s (step {})", bad_time, bad_step);
    const std::string who =
        f.processes > 1 ? fmt::format("process {} of {} failed {}", f.process, f.processes, at) : "the run failed " + at;
    if (!whole)
      throw RunFailure(fmt::format("{}: {}\nIts state could not be saved (the error cut short an exchange of "
                                   "particles between processes); the last checkpoint written is in {}.",
                                   who, f.message, options_.output_dir.string()));
    save_last_good_state();
    if (f.kind == kUnstable)
      throw InstabilityError(describe_instability(f.processes > 1 ? f.describe() : f.message, Health{}, bad_time,
                                                  bad_step, *sim_, schedule_.next_frame(), options_.output_dir));
    throw RunFailure(fmt::format(
        "{}: {}\nThe last good state (t = {:.6g} s, step {}) is saved as {}/frame_{:06} and {} in {}; `sluice run "
        "--restart {}` continues from it.",
        who, f.message, sim_->time(), sim_->clock().step, output_files::frames_dir, schedule_.next_frame(),
        output_files::checkpoint, options_.output_dir.string(),
        (options_.output_dir / output_files::checkpoint).string()));
  }

  void save_last_good_state() {
    outputs_.write_frame(schedule_.next_frame(), *sim_, wall());
    outputs_.write_checkpoint_file(*sim_, wall());
    progress_.finish();
  }

  void write_due_outputs() {
    const double t = sim_->time();
    if (schedule_.frame_due(t)) {
      outputs_.write_frame(schedule_.next_frame(), *sim_, wall());
      frame_is_current_ = true;
      schedule_.frame_written(t);
    }
    if (schedule_.checkpoint_due(t)) {
      write_checkpoint();
      schedule_.checkpoint_written(t);
    }
  }

  // What a normal end writes, also after Ctrl-C: the last frame, a checkpoint, the summary.
  RunResult finish() {
    if (!frame_is_current_) outputs_.write_frame(schedule_.next_frame(), *sim_, wall());
    outputs_.write_checkpoint_file(*sim_, wall());
    RunResult r = result();
    on_root(options_.comm, [&] { write_file_atomic(options_.output_dir / output_files::summary, format_summary(r)); });
    return r;
  }

  [[nodiscard]] RunResult result() const {
    const Case& c = sim_->config();
    RunResult r;
    r.final = sim_->diagnostics();
    r.particles = sim_->particle_count();
    r.steps_this_run = steps_;
    r.force_evaluations_per_step = sim_->force_evaluations_per_step();
    r.wall_seconds = wall();
    r.loop_seconds = seconds_since(loop_start_);
    r.particle_steps_per_second = r.loop_seconds > 0 ? particle_steps_ / r.loop_seconds : 0.0;
    r.frames_written = outputs_.frames_written();
    r.interrupted = interrupted_;
    r.rest_density = c.rest_density;
    r.sound_speed = c.sound_speed;
    r.single_precision_pairs = c.pair_precision == Precision::single;
    r.output_dir = options_.output_dir;
    r.case_name = c.name;
    r.notes = sim_->setup_notes();
    r.processes = options_.comm != nullptr ? options_.comm->size() : 1;
    sim_->visit([&](const auto& solver) {
      if (const auto* d = solver.distribution()) {
        r.bytes_exchanged = options_.comm->reducer().sum(d->bytes_sent() - bytes_before_);
        r.exchange_seconds = options_.comm->reducer().max(d->exchange_seconds() - exchange_seconds_before_);
        const double builds = static_cast<double>(std::max<std::int64_t>(d->ghost_builds(), 1));
        r.ghost_share = options_.comm->reducer().sum(d->ghosts_made() / builds) / static_cast<double>(r.particles);
      }
    });
    return r;
  }

  const RunOptions& options_;
  steady::time_point wall_start_;
  steady::time_point loop_start_;
  bool fresh_;
  std::unique_ptr<Simulation> sim_;
  Outputs outputs_;
  Schedule schedule_;
  Progress progress_;
  std::int64_t steps_ = 0;
  // On all processes: constant through a run but for the water that leaves an open tank (outflow_).
  std::size_t particles_ = sim_->particle_count();
  std::int64_t outflow_ = sim_->clock().outflow;
  double particle_steps_ = 0.0;  // the particles of each step of this run, summed
  bool mid_step_ = false;        // in Simulation::step
  double bytes_before_ = 0.0, exchange_seconds_before_ = 0.0;  // the set-up's exchanges
  bool interrupted_ = false;
  double checkpoint_wall_interval_ = sim_->config().checkpoint_wall_interval;  // 0: none while running
  steady::time_point last_checkpoint_;
  // A restart's state at the checkpoint time is already on disk (or, at a non-frame time, needs no frame).
  bool frame_is_current_ = true;
};

}  // namespace

bool fails_alike(const std::exception& e) {
  return dynamic_cast<const CaseError*>(&e) != nullptr || dynamic_cast<const IoError*>(&e) != nullptr ||
         dynamic_cast<const FormatError*>(&e) != nullptr || dynamic_cast<const InstabilityError*>(&e) != nullptr ||
         dynamic_cast<const RunFailure*>(&e) != nullptr;
}

std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr)
    return "out of memory (std::bad_alloc); use a coarser domain.dx, or spread the run over more processes and "
           "machines";
  const std::string what = e.what();
  return what.empty() ? "an error without a message" : what;
}

RunResult run_case(const Case& requested, const RunOptions& options, std::ostream& log) {
  const auto wall_start = steady::now();
  if (!options.restart) check_memory(requested, options.comm);
  Start start = options.restart ? start_from_checkpoint(options)
                                : Start{std::make_unique<Simulation>(requested, options.threads, options.comm)};
  check_start(*start.sim, options);
  check_output_plan(*start.sim);
  const double bytes = planned_frame_bytes(*start.sim);
  // Held until the run returns or throws: no second run writes into this directory meanwhile.
  std::optional<DirectoryLock> lock;
  on_root(options.comm, [&] {
    std::error_code ec;
    const bool existed = std::filesystem::exists(options.output_dir, ec);
    create_directories_or_throw(options.output_dir);
    try {
      check_room(options.output_dir, bytes, *start.sim);
    } catch (const IoError&) {
      if (!existed) std::filesystem::remove(options.output_dir, ec);
      throw;
    }
    lock.emplace(options.output_dir, fmt::format("{} {}", options.command, start.sim->config().name));
    prepare_output_dir(options.output_dir, start.sim->config().name, !options.restart);
  });
  Run run(std::move(start), options, log, wall_start);
  return run.to_end();
}

std::string format_summary(const RunResult& r) {
  const Diagnostics& d = r.final;
  std::string s;
  s += fmt::format("sluice {}: case '{}' {} at t = {:.4f} s\n", SLUICE_VERSION, r.case_name,
                  r.interrupted ? "stopped on request" : "finished", d.time);
  s += fmt::format("  particles   {} ({} fluid, {} wall)\n", r.particles, d.fluid_particles, d.wall_particles);
  s += fmt::format("  steps       {} ({} force evaluation{} per step), {} in this run\n", d.step,
                   r.force_evaluations_per_step, r.force_evaluations_per_step == 1 ? "" : "s", r.steps_this_run);
  if (r.processes > 1) {
    s += fmt::format("  processes   {} (MPI; the particles split among them by recursive coordinate bisection)\n",
                     r.processes);
    const double steps = static_cast<double>(std::max<std::int64_t>(r.steps_this_run, 1));
    s += fmt::format("  exchanges   {:.3f} MB per step between processes, {:.2f} ms per step ({:.1f} % of the loop); "
                     "ghosts {:.1f} % of the particles\n",
                     r.bytes_exchanged / steps * 1e-6, r.exchange_seconds / steps * 1e3,
                     r.loop_seconds > 0 ? 100.0 * r.exchange_seconds / r.loop_seconds : 0.0, 100.0 * r.ghost_share);
  }
  s += fmt::format("  wall time   {:.2f} s for this run\n", r.wall_seconds);
  s += fmt::format("  loop time   {:.3f} s stepping (without set-up and final output)\n", r.loop_seconds);
  s += fmt::format("  speed       {:.2f} M particle-steps/s, {:.2f} M particle-evaluations/s\n",
                   r.particle_steps_per_second * 1e-6,
                   r.particle_steps_per_second * r.force_evaluations_per_step * 1e-6);
  s += fmt::format("  pair loop   {} (the instruction set it ran on), {} precision\n", simd_target(),
                   r.single_precision_pairs ? "single" : "double");
  s += fmt::format("  leaks       {} (fluid particles put back from inside a wall)\n", d.leaks);
  if (d.outflow > 0)
    s += fmt::format("  outflow     {} (fluid particles that went over the open tank's walls, removed)\n", d.outflow);
  s += fmt::format("  density     min {:.2f}, max {:.2f} kg/m^3 (rho0 = {})\n", d.min_density, d.max_density,
                   r.rest_density);
  s += fmt::format("  max speed   {:.3f} m/s (c0 = {} m/s)\n", d.max_speed, r.sound_speed);
  s += fmt::format("  all finite  {}\n", d.all_finite ? "yes" : "NO");
  s += fmt::format("  output      {} ({} frames written)\n", r.output_dir.string(), r.frames_written);
  for (const std::string& n : r.notes) s += fmt::format("  note        {}\n", n);
  return s;
}

}  // namespace sluice
