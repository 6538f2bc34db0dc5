// The solver in Dim dimensions: particles, their neighbour grid, the physics settings and the clock.
// A Solver is a value: two of them can live side by side (no global state). Simulation
// (simulation.hpp) holds a Solver<2> or a Solver<3>, as the case says.
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/reduce.hpp"
#include "sluice/geometry/leaks.hpp"
#include "sluice/geometry/wall_ghosts.hpp"
#include "sluice/geometry/solid.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/solver/bodies.hpp"
#include "sluice/solver/distribution.hpp"
#include "sluice/physics/density_gradient.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/rates.hpp"
#include "sluice/physics/shifting.hpp"
#include "sluice/physics/wall_friction.hpp"

namespace sluice {

// Everything besides the particles that a restart needs to continue exactly.
struct Clock {
  double time = 0.0;
  std::int64_t step = 0;
  double last_dt = 0.0;
  std::int64_t leaks = 0;  // fluid particles put back from inside a wall, summed over the run
  // Fluid particles that left an open tank (beyond its walls' reach, Solver::within_walls) and were
  // removed, summed over the run.
  std::int64_t outflow = 0;
  // The leapfrog carries the rates of a step's end into the next step: while `rates_carried`, the
  // particles' acceleration and density_rate are a(n), D(n) of the current state (evaluated at its
  // positions with the predicted v*, rho*: integrate/integrators.hpp) and `rates` their summary, which
  // chooses the next dt. Anything that changes the state outside an evaluation (a particle put back
  // from inside a wall) clears it, and the next step evaluates first.
  bool rates_carried = false;
  RateSummary rates{};
  // The absorbing pistons' states (Bodies::absorber_state): what their corrections are made of so far.
  std::vector<double> absorbers;
  // The floating bodies' states (Bodies::floating_state): pose, rates and the loads of the last
  // evaluation, whose accelerations the leapfrog carries.
  std::vector<double> floating;
};

struct Diagnostics {
  double time = 0.0;
  std::int64_t step = 0;
  double dt = 0.0;
  std::size_t fluid_particles = 0;
  std::size_t wall_particles = 0;
  double max_speed = 0.0;        // fluid
  double min_density = 0.0;      // all particles
  double max_density = 0.0;      // all particles
  double kinetic_energy = 0.0;   // fluid; J per metre of depth in 2D
  double potential_energy = 0.0; // fluid, relative to the origin: -m g . x
  double total_mass = 0.0;       // fluid
  std::int64_t leaks = 0;
  std::int64_t outflow = 0;  // fluid particles removed after leaving an open tank, summed over the run
  bool all_finite = true;
  // Fluid to any particle, at the evaluation of the state the last step started from (its first; the
  // leapfrog's carried one); NaN before the first step.
  double min_particle_distance = 0.0;
};

// A particle that makes a run unusable: non-finite, far outside the tank, or at an absurd density.
struct Offender {
  std::uint32_t id = 0;
  int dimension = 2;
  Vec3 position{};
  Vec3 velocity{};
  double density = 0.0;
  int neighbours = 0;  // particles within the kernel support
  std::string reason;
};

struct Health {
  std::size_t offending = 0;       // how many particles are bad
  std::vector<Offender> first;     // the first few, in id order
  std::string wall_outside;        // a moving wall outside the tank: which, and where (else empty)
  [[nodiscard]] bool ok() const { return offending == 0 && wall_outside.empty(); }
};

template <int Dim>
class Solver {
 public:
  using KernelVariant = AnyKernel<Dim>;

  // Builds the particles of a case (setup) and starts at t = 0. With a communicator of several
  // processes, every process builds the same particles and keeps those in its region
  // (solver/distribution.hpp); without one (or with one process), this process holds them all.
  Solver(const Case& c, int threads, const Communicator* comm = nullptr);
  // Continues from a saved state (restart): all the particles, on any number of processes.
  Solver(const Case& c, Particles<Dim> particles, Clock clock, int threads, const Communicator* comm = nullptr);

  // Advances one time step; a step that would pass time_limit ends exactly on it.
  void step(double time_limit);

  // This process's particles (all of them with one process).
  [[nodiscard]] const Particles<Dim>& particles() const { return particles_; }
  // The particles of every process, on the root process in particle-id order: f(particles) there, and
  // nothing elsewhere. With one process, f(particles()). Collective.
  template <class F>
  void with_all_particles(F&& f) const {
    if (!distribution_) {
      f(particles_);
      return;
    }
    using namespace field_role;
    const Particles<Dim> all = distribution_->gather(particles_, state | checkpoint | frame | carried);
    if (distribution_->comm().is_root()) f(all);
  }
  // Particles on all processes.
  [[nodiscard]] std::size_t particle_count() const {
    return distribution_ ? static_cast<std::size_t>(reducer_->sum(static_cast<std::int64_t>(particles_.size())))
                         : particles_.size();
  }
  // The process that writes the outputs (always, with one process).
  [[nodiscard]] bool is_root() const { return !distribution_ || distribution_->comm().is_root(); }
  // The domain decomposition, with several processes (else null).
  [[nodiscard]] const Distribution<Dim>* distribution() const { return distribution_.get(); }
  [[nodiscard]] const Clock& clock() const { return clock_; }
  [[nodiscard]] const Case& config() const { return case_; }
  [[nodiscard]] const Solids<Dim>& solids() const { return solids_; }
  // The tank and the walls as bodies, the moving ones at the current time.
  [[nodiscard]] const Bodies<Dim>& bodies() const { return bodies_; }
  // The force the water exerts on a body's wall particles through the pair terms (pressure and
  // viscosity) at the last force evaluation, and its moment about the body's reference point (its
  // centre of rotation, where it is now): the sum of m a over the body's particles. In 2D the moment
  // is about z (its third component). On all processes; collective.
  struct BodyLoad {
    Vec<Dim> force{};
    Vec3 moment{};
  };
  [[nodiscard]] BodyLoad body_load(std::uint8_t body) const;
  [[nodiscard]] const KernelVariant& kernel() const { return kernel_; }
  [[nodiscard]] double particle_mass() const { return settings_.mass; }
  [[nodiscard]] double smoothing_length() const { return settings_.h; }
  [[nodiscard]] const TaitEos& eos() const { return settings_.eos; }
  [[nodiscard]] std::size_t removed_near_coincident() const { return removed_near_coincident_; }
  // What the set-up has to tell the user (Setup::notes); none for a solver restarted from a checkpoint.
  [[nodiscard]] const std::vector<std::string>& setup_notes() const { return setup_notes_; }
  [[nodiscard]] int force_evaluations_per_step() const {
    return case_.integrator == Integrator::predictor_corrector ? 2 : 1;
  }
  // Force evaluations made by this solver since it was built (the leapfrog: one per step, and one more
  // at a step that starts without carried rates: the first, and the one after a leak).
  [[nodiscard]] std::int64_t force_evaluations() const { return evaluations_; }
  [[nodiscard]] int threads() const { return threads_; }
  // The threads of the steps from now on (the results are the same bits on any count).
  void set_threads(int threads) { threads_ = threads < 1 ? 1 : threads; }
  // The particle shift of the last step (zone, div r, shift velocity), when shifting is on.
  [[nodiscard]] const ParticleShifting<Dim>& shifting() const { return shift_; }
  // Combines the sums and maxima of this process's particles with those of the others.
  [[nodiscard]] const Reducer& reducer() const { return *reducer_; }
  [[nodiscard]] Diagnostics diagnostics() const;

  // Calls f(begin, end) for ranges of particle indices, in increasing order, that hold every particle
  // inside the box [lower, upper] (and others: the caller checks positions). Uses the cell grid of the
  // last force evaluation, whose cells the particles have left by less than a cell since (a step moves
  // a particle by less than h); before the first evaluation, all particles.
  template <class F>
  void for_each_range_in_box(Vec<Dim> lower, Vec<Dim> upper, F&& f) const {
    if (!grid_binned_) {
      f(std::uint32_t{0}, static_cast<std::uint32_t>(particles_.size()));
      return;
    }
    for (int d = 0; d < Dim; ++d) {
      lower[d] -= grid_.cell_size();
      upper[d] += grid_.cell_size();
    }
    grid_.for_each_range_in_box(lower, upper, f);
  }

  // The instability guard: every particle finite, within the tank's reach (in_reach), and
  // 0.5 rho0 < rho < 2 rho0. Water that leaves an open tank has been removed before (finish_step).
  [[nodiscard]] Health check_health(std::size_t max_reported) const;

  // The bounds of within_walls and in_reach, made once for a pass over the particles. The walls'
  // reach: sideways inside the walls' outer faces plus a margin (the wall layers and 4h), and above
  // the floor's underside less that margin; water can leave it only over the walls of an open tank (or
  // through a wall, when a run has gone unstable). The tank's reach: within the walls' reach, and no
  // higher than the lid plus that margin or, above an open tank, ten times the tank's height (a jet
  // thrown up falls back; one thrown that high is taken for an instability).
  static constexpr double kLargest = std::numeric_limits<double>::max();  // |x| <= it: x is finite
  struct Reach {
    Vec<Dim> lower{}, upper{};  // the walls' reach: lower <= x, and x <= upper along all but the vertical
    double top = 0.0;           // the tank's reach: also x[vertical] <= top
  };
  [[nodiscard]] Reach reach() const;
  // Branch-free, so that the passes over every particle at every step vectorise. A coordinate that is
  // not finite is outside either.
  [[nodiscard]] bool within_walls(std::size_t i, const Reach& r) const {
    constexpr int up = Dim - 1;
    bool inside = particles_.position[up][i] >= r.lower[up];
    for (int d = 0; d < up; ++d)
      inside = inside & (particles_.position[d][i] >= r.lower[d]) & (particles_.position[d][i] <= r.upper[d]);
    return inside;
  }
  [[nodiscard]] bool in_reach(std::size_t i, const Reach& r) const {
    return within_walls(i, r) & (particles_.position[Dim - 1][i] <= r.top);
  }
  // The instability guard's test of particle i (check_health), branch-free: a density or position that
  // is not finite fails its range, a velocity that is not finite its bound.
  [[nodiscard]] bool healthy(std::size_t i, const Reach& r) const {
    const Particles<Dim>& p = particles_;
    const double rho = p.density[i], rho0 = settings_.eos.rest_density;
    // A wall particle is where its wall is (a moving one may rise out of an open tank): finite is enough.
    bool placed = !p.is_fluid(i);
    for (int d = 0; d < Dim; ++d) placed = placed & (std::abs(p.position[d][i]) <= kLargest);
    bool ok = (rho > 0.5 * rho0) & (rho < 2.0 * rho0) & (in_reach(i, r) | placed);
    for (int d = 0; d < Dim; ++d) ok = ok & (std::abs(p.velocity[d][i]) <= kLargest);
    return ok;
  }
  // Fluid that has left an open tank (remove_outflow). A particle that is not finite is the guard's
  // (check_health), not outflow.
  [[nodiscard]] bool leaves(std::size_t i, const Reach& r) const {
    bool finite = true;
    for (int d = 0; d < Dim; ++d) finite = finite & (std::abs(particles_.position[d][i]) <= kLargest);
    return particles_.is_fluid(i) & finite & !within_walls(i, r);
  }

  // Coupling with another code between steps (the Python module's hooks).
  //
  // Sets the velocities of the fluid particles `ids`, Dim values each in `velocity` (row-major). With
  // several processes, ids this process does not hold are skipped; with one, an id that is no
  // particle is an error (std::invalid_argument), as is a wall particle (walls move as their motion
  // says) or a value that is not finite. The rates a leapfrog carries into the next step were those
  // of the old velocities, so the next step evaluates them first. Returns how many were set here.
  std::size_t set_fluid_velocities(std::span<const std::uint32_t> ids, std::span<const double> velocity);
  // An acceleration of the water besides gravity, added at every force evaluation: f(t, n, x, a) is
  // given the n fluid particles' positions x (n x Dim, row-major) at the evaluation's time t, and
  // fills a (n x Dim, zeroed) in m/s^2. It counts in the time step's acceleration limit. An empty f
  // removes it. A value that is not finite stops the step (std::invalid_argument).
  using ExternalAcceleration = std::function<void(double t, std::size_t n, const double* x, double* a)>;
  void set_external_acceleration(ExternalAcceleration f) { external_acceleration_ = std::move(f); }

  // Returns to the state at the start of the last step (if it got far enough to change anything),
  // for the instability guard and after a failure mid-step; drops the ghosts of a step cut short.
  void restore_saved_state();
  // The last step saved its starting state (it got as far as changing the particles): cleared when a
  // step starts, set once its first evaluation is done.
  [[nodiscard]] bool has_saved_state() const { return has_saved_state_; }

 private:
  void absorb();
  void load_floating();
  // `built`: the particles as the case's set-up made them (the walls at their start pose).
  void init(const Case& c, const Particles<Dim>& built);
  // Moves the moving walls to time t: their bodies' states and solids, their particles' positions and
  // velocities, mDBC's ghost nodes. The one place where walls move; every integrator calls it when
  // its particles reach a stage's time.
  void advance_walls(double t);
  // With several processes: the decomposition, and this process's share of the full set of particles.
  void distribute(const Communicator* comm);
  // Drops the ghosts of the last evaluation (several processes), with their cells in the grid.
  void strip_ghosts();
  // Rebuilds the neighbour grid (reordering the particles by cell, and with them the fields of the
  // roles `also_moved`: field_role::step_start, rates_start during a step), applies the Shepard filter
  // when due and any pending density repairs, and computes the rates; at the step's last evaluation
  // (`last`), also the particle shift when it is on.
  RateSummary evaluate(bool shepard_due, unsigned also_moved, bool last);
  // One step of the leapfrog (integrate/integrators.hpp).
  void leapfrog_step(double time_limit, bool shepard_due);
  // This process's maxima and minimum combined with the other processes' (reducer()).
  RateSummary global(const RateSummary& r) const;
  double choose_dt(const RateSummary& r) const;
  // choose_dt, checked (throws if not a positive finite number) and cut to land on time_limit.
  struct StepSize {
    double dt;
    bool reaches_limit;
    // The time at the step's end, from its start: exactly the limit when it reaches it.
    [[nodiscard]] double end(double start, double time_limit) const { return reaches_limit ? time_limit : start + dt; }
  };
  StepSize step_size(const RateSummary& r, double time_limit) const;
  // After the update: the particle shift, the put-back of leaked particles, the outflow, the clock.
  // What follows every integrator's update; `final_kick` folds the leapfrog's final kick into its sweep.
  void finish_step(const StepSize& size, double time_limit, bool final_kick = false);
  // One sweep over the particles after an update: the leapfrog's final kick (with `final_kick`), the
  // damping zone, the shift, the put-back of leaked particles, and the counts of the outflow and of
  // the instability guard, each particle taken through all of them in turn.
  struct SweepCounts {
    std::int64_t leaked = 0;     // put back from inside a wall
    std::int64_t leaving = 0;    // fluid that left an open tank, to remove
    std::int64_t unhealthy = 0;  // of the particles that stay, those check_health counts
  };
  SweepCounts sweep_after_update(double dt, bool final_kick);
  // The sweeps take their stages in turn on blocks of this many particles, which stay in the core's
  // second-level cache from one stage to the next (about 300 kB in 3D, at most about 150 bytes a
  // particle), in runs long enough for the hardware prefetchers.
  static constexpr long sweep_block = 2048;
  // The leapfrog's stage 1 with the wall-approach stop before it, in one sweep.
  void kick_drift_sweep(double dt);
  // An open tank: removes the fluid particles beyond its walls' reach (`leaving_here` of them on this
  // process, as the sweep counted) and counts them (Clock::outflow); returns how many left, on all
  // processes.
  std::int64_t remove_outflow(std::int64_t leaving_here);
  // Before a drift: physics.wall_no_penetration (geometry/leaks.hpp).
  // Adds external_acceleration_'s values to the fluid's (evaluate).
  void add_external_acceleration(RateSummary& summary);
  void stop_wall_approach_before_drift(const typename Particles<Dim>::template Vector<double>* acceleration, double tau);

  Case case_;
  Particles<Dim> particles_;
  ExternalAcceleration external_acceleration_;
  double stage_time_ = 0.0;  // the time the walls were last moved to: the evaluation's
  Solids<Dim> solids_;
  Bodies<Dim> bodies_;
  // A moving tank: the box its walls sweep over the run, which the reach of the water takes in.
  std::optional<std::pair<Vec<Dim>, Vec<Dim>>> tank_swept_;
  // mDBC with moving walls: the ghost nodes, those of moving bodies' particles carried to the current
  // pose from their start (ghost_start_, by id) by advance_walls.
  std::shared_ptr<WallGhosts<Dim>> ghosts_;
  std::vector<Vec<Dim>> ghost_start_;
  SolidReach<Dim> solid_reach_;  // where the leak checks can skip the water
  SolidReach<Dim> friction_reach_;  // where the wall friction can skip the water (reach 2h)
  WallFrictionSettings friction_{};
  CellGrid<Dim> grid_;
  bool grid_binned_ = false;
  KernelVariant kernel_{CubicSpline<Dim>(1.0)};
  WallTreatment walls_;
  RateSettings<Dim> settings_{};
  ParticleTerms terms_;
  DensityGradient<Dim> rho_gradient_;  // physics.density_diffusion_gradient = "renormalised"
  Vec<Dim> pair_origin_{};  // the middle of the tank: single-precision positions are relative to it
  ShiftingSums shifting_sums_{};
  ShiftingSettings shifting_{};
  ParticleShifting<Dim> shift_;
  std::vector<double> scratch_;
  Clock clock_;
  double min_particle_distance_ = std::numeric_limits<double>::quiet_NaN();  // unknown before the first step
  Clock saved_clock_;
  bool has_saved_state_ = false;
  // The guard's count of this process's unhealthy particles, taken in the last step's final sweep
  // (sweep_after_update): check_health uses it while the particles are as that step left them.
  std::optional<std::int64_t> swept_unhealthy_;
  std::int64_t evaluations_ = 0;
  int threads_ = 1;
  const Reducer* reducer_ = &serial_reducer();
  std::unique_ptr<Distribution<Dim>> distribution_;
  std::size_t removed_near_coincident_ = 0;
  std::vector<std::string> setup_notes_;
};

extern template class Solver<2>;
extern template class Solver<3>;

}  // namespace sluice
