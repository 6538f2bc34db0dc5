#include "sluice/io/run_checks.hpp"

#include <fmt/format.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <tuple>
#include <utility>

#include "sluice/case/case_error.hpp"
#include "sluice/case/params.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/schedule.hpp"

namespace sluice {

namespace {

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

}  // namespace

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

// The state a run starts from passes the instability guard, or the run does not start: a case whose
// set-up is already unusable (water at an absurd hydrostatic density), or a checkpoint whose values
// are not a state a run can reach (a crafted file whose checksum passes), is refused before anything
// is written. Collective.
void check_start(const Simulation& sim, const std::filesystem::path& restart) {
  const Health health = sim.check_health();
  if (health.ok()) return;
  if (!restart.empty()) {
    std::string offenders = describe_offenders(health);
    offenders.pop_back();  // its last line's newline
    throw CaseError(fmt::format("{}: not a usable checkpoint: {}", restart.string(), offenders));
  }
  throw CaseError(fmt::format(
      "the case's initial state is unusable: {}Usual causes: a sound speed (fluid.sound_speed) too low for the "
      "water's depth under the hydrostatic start (physics.hydrostatic_start), or an initial pressure "
      "(physics.initial_pressure) beyond what the equation of state allows.",
      describe_offenders(health)));
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
  const double frames = planned_frames(c, sim.time());
  if (frames > static_cast<double>(c.max_frames))
    throw CaseError(fmt::format(
        "the run would write {:.0f} frames (time.end = {} s every output.interval = {} s), more than "
        "output.max_frames = {}; expected a longer output.interval, or a larger output.max_frames to write that "
        "many",
        frames, c.end_time, c.output_interval, c.max_frames));
}

// The bytes of the frames a run plans to write: the .npz holds x, v (Dim components each), rho and p as
// doubles, kind (1 byte) and id (4) per particle; the .vtu the same with 3 components for x and v, and
// its cells (about 90 bytes a particle).
double planned_frame_bytes(const Simulation& sim) {
  const Case& c = sim.config();
  const double dim = c.dimension;
  const double per_particle = (c.writes("npz") ? 8.0 * (2.0 * dim + 2.0) + 5.0 : 0.0) + (c.writes("vtk") ? 90.0 : 0.0);
  return planned_frames(sim.config(), sim.time()) * per_particle * static_cast<double>(sim.particle_count());
}

// The output directory (existing) has room for the frames planned, or the run does not start.
void check_room(const std::filesystem::path& dir, double bytes, const Simulation& sim) {
  std::error_code ec;
  const std::filesystem::space_info space = std::filesystem::space(dir, ec);
  if (ec || space.capacity == 0 || bytes <= static_cast<double>(space.available)) return;  // (/proc: no size)
  throw IoError(fmt::format(
      "{}: the run would write about {:.3g} GB of frames ({:.0f} frames of {} particles), and {} has {:.3g} GB "
      "free; expected a longer output.interval, fewer output.formats, or more room",
      dir.string(), bytes * 1e-9, planned_frames(sim.config(), sim.time()),
      sim.particle_count(), dir.parent_path().string(), static_cast<double>(space.available) * 1e-9));
}

}  // namespace sluice
