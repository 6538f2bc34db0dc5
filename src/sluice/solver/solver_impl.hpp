// The definitions of Solver<Dim>, compiled once per dimension (solver_2d.cpp, solver_3d.cpp), so
// that the two build side by side. The pair loop is compiled apart, per instruction set
// (physics/pair_loop_*.cpp).
#pragma once

#include "sluice/solver/solver.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/geometry/leaks.hpp"
#include "sluice/physics/damping.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/integrate/integrators.hpp"
#include "sluice/solver/free_surface.hpp"

namespace sluice {

// In a case with a wave maker or an absorbing piston, a surface gauge reads waves from the still
// level it starts at: one whose vertical line has no water at the start (within a particle spacing
// of it) stands outside the water column, and is refused.
template <int Dim>
void check_surface_gauges_in_water(const Case& c, const Particles<Dim>& built) {
  const auto waves = [](const MotionLawSpec& m) {
    return m.law == MotionLawType::wave || m.law == MotionLawType::absorber;
  };
  if (std::none_of(c.walls.begin(), c.walls.end(),
                   [&](const Region& w) { return waves(w.translation) || waves(w.rotation); }))
    return;
  for (const Probe& probe : c.probes) {
    if (probe.type != ProbeType::gauge || probe.measure != GaugeMeasure::surface || !probe.wall.empty()) continue;
    bool wet = false;
    for (std::size_t i = 0; i < built.size() && !wet; ++i) {
      if (!built.is_fluid(i)) continue;
      double across2 = 0.0;
      for (int d = 0; d < Dim - 1; ++d) across2 += (built.position[d][i] - probe.point[d]) * (built.position[d][i] - probe.point[d]);
      wet = across2 <= c.dx * c.dx && built.position[Dim - 1][i] >= probe.point[Dim - 1];
    }
    if (!wet)
      throw CaseError(fmt::format(
          "[[probe]] \"{}\": the surface gauge's vertical line up from {} has no water on it at the start; in a "
          "wave flume a surface gauge must stand in the still water, whose level its waves are measured from "
          "(for the water's reach up a beach, use a front probe)",
          probe.name, format_vector(probe.point, Dim)));
  }
}

template <int Dim>
Solver<Dim>::Solver(const Case& c, int threads, const Communicator* comm) : threads_(std::max(1, threads)) {
  Setup<Dim> s = build_setup<Dim>(c);
  check_surface_gauges_in_water(c, s.particles);
  bodies_ = Bodies<Dim>(c, s.particles, s.solids);
  clock_.absorbers = bodies_.absorber_state();
  clock_.floating = bodies_.floating_state();
  bodies_.check_inside_tank(c.end_time, c.tank_size(), c.tank_lid);
  bodies_.check_apart(s.particles, s.solids, c.walls);
  particles_ = std::move(s.particles);
  particles_.resize(particles_.size());  // size the rate and step-start fields
  solids_ = std::move(s.solids);
  removed_near_coincident_ = s.removed_near_coincident;
  setup_notes_ = std::move(s.notes);
  init(c, particles_);
  distribute(comm);
}

// A saved state must be one its case made: as many particles as the case builds (less those removed
// as outflow), each of the kind the case gave it, and the walls where the case puts them (a moving
// wall where its motion has taken it at the saved time: `bodies` at that time). A state saved with
// another dx, tank or wall would otherwise run as if it were the case's.
template <int Dim>
void check_saved_particles_match(const Particles<Dim>& built, const Particles<Dim>& saved, std::int64_t outflow,
                                 const Case& c, const Bodies<Dim>& bodies) {
  const std::size_t expected = built.size();
  if (saved.size() + static_cast<std::size_t>(outflow) != expected)
    throw CaseError(fmt::format(
        "{} particles{}, where its case (domain.dx = {} m) builds {}: the particles were not made by the case "
        "stored with them",
        saved.size(), outflow > 0 ? fmt::format(" and {} removed as outflow", outflow) : std::string(), c.dx,
        expected));
  const double tolerance = 1e-6 * c.dx;
  for (std::size_t i = 0; i < saved.size(); ++i) {
    const std::uint32_t id = saved.id[i];
    if (id >= expected) continue;  // the reader checked the ids; a crafted one is refused there
    if (saved.kind[i] != built.kind[id])
      throw CaseError(fmt::format("particle id {} is {}, where its case has {}: the particles were not made by the "
                                  "case stored with them",
                                  id, saved.is_fluid(i) ? "water" : "a wall particle",
                                  built.is_fluid(id) ? "water" : "a wall particle"));
    if (saved.is_fluid(i)) continue;
    Vec<Dim> expected_at{};
    for (int d = 0; d < Dim; ++d) expected_at[d] = built.position[d][id];
    const std::uint8_t body = built.body[id];
    if (bodies.motion().moves(body)) expected_at = bodies.carried(body, expected_at);
    double off = 0.0;
    for (int d = 0; d < Dim; ++d) off = std::max(off, std::abs(saved.position[d][i] - expected_at[d]));
    if (!(off <= tolerance)) {
      std::string at, where;
      for (int d = 0; d < Dim; ++d) {
        at += fmt::format("{}{:.6g}", d ? ", " : "", saved.position[d][i]);
        where += fmt::format("{}{:.6g}", d ? ", " : "", expected_at[d]);
      }
      throw CaseError(fmt::format("wall particle id {} is at ({}) m, where its case (domain.dx = {} m) puts it at "
                                  "({}) m: the particles were not made by the case stored with them",
                                  id, at, c.dx, where));
    }
  }
}

template <int Dim>
Solver<Dim>::Solver(const Case& c, Particles<Dim> particles, Clock clock, int threads, const Communicator* comm)
    : particles_(std::move(particles)), clock_(clock), threads_(std::max(1, threads)) {
  // The wall geometry is rebuilt from the case; the particles come from the saved state, which must
  // be one the case made.
  Setup<Dim> built = build_setup<Dim>(c);
  bodies_ = Bodies<Dim>(c, built.particles, built.solids);
  bodies_.set_absorber_state(clock_.absorbers);
  bodies_.set_floating_state(clock_.floating);
  bodies_.set_time(clock_.time);
  check_saved_particles_match(built.particles, particles_, clock_.outflow, c, bodies_);
  // A particle's body is its case's (a checkpoint before format 5 has none).
  for (std::size_t i = 0; i < particles_.size(); ++i) particles_.body[i] = built.particles.body[particles_.id[i]];
  solids_ = std::move(built.solids);
  init(c, built.particles);
  distribute(comm);
}

template <int Dim>
void Solver<Dim>::distribute(const Communicator* comm) {
  if (comm == nullptr || comm->size() < 2) return;
  // A process must see the particles within the kernel support of its own; mDBC's wall particles
  // also read the water around their ghost nodes, mirrored up to the wall's thickness into the water.
  double halo = 2.0 * settings_.h;
  if (case_.wall_boundary == WallBoundary::mdbc) halo += 2.0 * wall_layers(case_) * case_.dx;
  // The skin lets the predictor-corrector's second evaluation keep the ghosts of its first: a step
  // moves a particle by a small fraction of h (time.cfl), a half step by less than 0.1 h.
  distribution_ = std::make_unique<Distribution<Dim>>(*comm, halo * (1.0 + 1e-9), 0.2 * settings_.h);
  reducer_ = &comm->reducer();
  distribution_->distribute(particles_);
  // A process without particles has nothing to do: the case is too small for this many processes.
  if (reducer_->min(static_cast<double>(particles_.size())) == 0.0)
    throw CaseError(fmt::format(
        "{} processes for {} particles: the domain decomposition leaves a process without any; run on fewer "
        "processes (mpirun -np N) or with a finer domain.dx",
        comm->size(), particle_count()));
}

template <int Dim>
void Solver<Dim>::strip_ghosts() {
  if (!distribution_ || !distribution_->has_ghosts()) return;
  const std::vector<std::uint8_t> keep = distribution_->strip_ghosts(particles_);
  if (grid_binned_) grid_.keep(keep);
}

template <int Dim>
void Solver<Dim>::init(const Case& c, const Particles<Dim>& built) {
  case_ = c;
  // Only the leapfrog carries rates from one step into the next, and only it uses the rates at a
  // step's start: the other integrators do not keep their memory.
  if (c.integrator != Integrator::leapfrog) {
    clock_.rates_carried = false;
    for (auto& component : particles_.acceleration_start) std::vector<double>().swap(component);
    std::vector<double>().swap(particles_.density_rate_start);
  }
  const double h = c.smoothing_length();
  settings_.mass = c.rest_density;
  for (int d = 0; d < Dim; ++d) settings_.mass *= c.dx;  // rho0 dx^Dim
  settings_.h = h;
  settings_.viscosity = c.viscosity;
  settings_.alpha = c.artificial_viscosity;
  settings_.artificial_pressure = c.artificial_pressure;
  settings_.artificial_pressure_exponent = c.artificial_pressure_exponent;
  settings_.spacing = c.dx;
  settings_.delta = c.density_diffusion;
  settings_.gravity = first<Dim>(c.gravity);
  settings_.eos = TaitEos{c.rest_density, c.sound_speed, c.gamma};
  settings_.wall_pair_pressure_floor = c.wall_tension ? -std::numeric_limits<double>::infinity() : 0.0;
  if (c.kernel == KernelType::wendland_c2) kernel_ = WendlandC2<Dim>(h);
  else kernel_ = CubicSpline<Dim>(h);
  shifting_ = ShiftingSettings{c.shifting, c.free_surface_threshold};
  shifting_sums_.h = h;
  shifting_sums_.spacing = c.dx;
  shifting_sums_.volume = settings_.mass / c.rest_density;
  if (c.wall_boundary == WallBoundary::adami) walls_ = AdamiWalls{};
  else if (c.wall_boundary == WallBoundary::mdbc) {
    if (bodies_.any_moving()) {
      ghosts_ = std::make_shared<WallGhosts<Dim>>(wall_ghosts(built, c));
      ghost_start_ = ghosts_->node;
      walls_ = MdbcWalls::of(std::shared_ptr<const WallGhosts<Dim>>(ghosts_), settings_.mass, c.wall_slip);
    } else {
      walls_ = MdbcWalls::of(wall_ghosts(built, c), settings_.mass, c.wall_slip);
    }
  } else {
    walls_ = DynamicWalls{};
  }
  // The grid covers the tank and its walls with a margin, and wherever a moving wall goes; strays are
  // clamped into edge cells.
  const int layers = wall_layers(c);
  const double margin = (layers + 2) * c.dx + 2.0 * h;
  const Vec3 size = c.tank_size();
  Vec<Dim> lower{}, upper{};
  for (int d = 0; d < Dim; ++d) {
    lower[d] = -margin;
    upper[d] = size[d] + margin;
  }
  // A moving wall's reach: the box it sweeps over the run, in place of its shape.
  const Solids<Dim> swept = bodies_.swept(c.end_time, 2.0 * h);
  if (c.tank_moves()) tank_swept_ = std::pair{swept.front()->lower(), swept.front()->upper()};
  Solids<Dim> reach_solids;
  for (const auto& solid : solids_)
    if (!dynamic_cast<const MovingSolid<Dim>*>(solid.get())) reach_solids.push_back(solid);
  for (const auto& box : swept) reach_solids.push_back(box);
  // A floating body's reach is marked where it is at each stage (advance_walls), not over the whole
  // tank it may go to, which would leave no water clear of the checks.
  Solids<Dim> extent = swept;
  for (const auto& box : bodies_.floating_extent(2.0 * h, size, c.tank_lid)) extent.push_back(box);
  for (const auto& box : extent)
    for (int d = 0; d < Dim; ++d) {
      lower[d] = std::min(lower[d], box->lower()[d]);
      upper[d] = std::max(upper[d], box->upper()[d]);
    }
  grid_ = CellGrid<Dim>(lower, upper, 2.0 * h);
  // The leak and wall-approach checks skip the water away from the walls (the wall-approach band is
  // dx/4 wide).
  solid_reach_ = SolidReach<Dim>(reach_solids, lower, upper, 2.0 * h, 0.25 * c.dx);
  if (wall_friction_in_effect(c) == WallFriction::log_law) {
    friction_ = WallFrictionSettings{c.viscosity / c.rest_density, h, c.dx};
    friction_reach_ = SolidReach<Dim>(reach_solids, lower, upper, 2.0 * h, 2.0 * h);
  }
  for (int d = 0; d < Dim; ++d) pair_origin_[d] = 0.5 * size[d];
  advance_walls(clock_.time);
}

template <int Dim>
void Solver<Dim>::advance_walls(double t) {
  stage_time_ = t;
  if (!bodies_.any_moving()) return;
  bodies_.set_time(t);
  bodies_.place(particles_, threads_);
  if (bodies_.floats()) {
    const auto floating = bodies_.floating_solids();
    solid_reach_.update(floating);
    friction_reach_.update(floating);
  }
  if (ghosts_) {
    for (const auto& body : bodies_.list()) {
      if (!body.moves) continue;
      for (std::size_t k = 0; k < body.start.size(); ++k) {
        const std::size_t id = body.first_id + k;
        if (ghosts_->has[id]) ghosts_->node[id] = bodies_.carried(body.id, ghost_start_[id]);
      }
    }
  }
}

template <int Dim>
RateSummary Solver<Dim>::evaluate(bool shepard_due, unsigned also_moved, bool last) {
  ++evaluations_;
  Distribution<Dim>* const dist = distribution_.get();
  if (dist) {
    // The predictor-corrector's second evaluation (its step-start state is the first's positions)
    // may keep the first's ghosts.
    double moved = std::numeric_limits<double>::infinity();
    if (case_.integrator == Integrator::predictor_corrector && also_moved == field_role::step_start &&
        dist->has_ghosts()) {
      const std::vector<std::uint8_t>& ghost = dist->ghost_mask();
      double most2 = 0.0;
      for (std::size_t i = 0; i < particles_.size(); ++i) {
        if (i < ghost.size() && ghost[i]) continue;
        double d2 = 0.0;
        for (int d = 0; d < Dim; ++d) {
          const double delta = particles_.position[d][i] - particles_.position_start[d][i];
          d2 += delta * delta;
        }
        most2 = std::max(most2, d2);
      }
      moved = std::sqrt(most2);
    }
    dist->before_evaluation(particles_, also_moved, moved);
  }
  grid_.bin(particles_.position, threads_);
  particles_.reorder(grid_.order(), scratch_, also_moved, threads_);
  // The neighbour loops share out work only above a size where it pays (core/parallel.hpp).
  const int pair_threads = static_cast<long>(particles_.size()) >= parallel::pair_loop_threshold ? threads_ : 1;
  if (dist) dist->reordered(grid_.order());
  grid_binned_ = true;
  // One thread: an OR over a byte a particle is quicker than starting the others.
  std::uint8_t any_repair = 0;
  for (const std::uint8_t r : particles_.needs_density_repair) any_repair |= r;
  bool repair_due = any_repair != 0;
  if (dist) repair_due = reducer_->sum(static_cast<std::int64_t>(repair_due)) > 0;
  if (shepard_due || repair_due) {
    // The density rates are recomputed below: until then their array is the filter's scratch.
    shepard_filter(particles_, grid_, kernel_, settings_.mass, shepard_due ? nullptr : &particles_.needs_density_repair,
                   particles_.density_rate, pair_threads);
    std::fill(particles_.needs_density_repair.begin(), particles_.needs_density_repair.end(), 0);
    if (dist) dist->refresh(particles_, {"density"});
  }
  std::visit([&](const auto& walls, const auto& kernel) {
    walls.before_rates(particles_, grid_, kernel, settings_.eos, settings_.gravity, pair_threads, &bodies_.motion());
  }, walls_, kernel_);
  if (dist && !std::holds_alternative<DynamicWalls>(walls_)) dist->refresh(particles_, {"density", "velocity"});
  terms_.compute(particles_, settings_.eos, settings_.gravity, threads_, settings_.artificial_pressure,
                 case_.pair_precision == Precision::single, pair_origin_);
  if (case_.diffusion_gradient == DiffusionGradient::renormalised && settings_.delta > 0.0) {
    rho_gradient_.compute(particles_, grid_, kernel_, settings_.mass, terms_.fluid_mask.data(), pair_threads);
    // A ghost's sum lacks the neighbours beyond this process's halo: its owner's value.
    if (dist)
      for (auto& g : rho_gradient_.gradient()) dist->refresh(g);
    terms_.set_rho_gradient(rho_gradient_.gradient(), threads_);
  }

  RateSummary summary = compute_rates(particles_, grid_, kernel_, walls_, settings_, terms_, pair_threads);
  if (wall_friction_in_effect(case_) == WallFriction::log_law) {
    const WallFrictionResult friction = add_wall_friction(particles_, solids_, friction_, threads_, &friction_reach_,
                                                          dist ? dist->ghost_mask().data() : nullptr);
    summary.max_acceleration = std::max(summary.max_acceleration, friction.max_acceleration);
  }
  if (external_acceleration_) add_external_acceleration(summary);
  if (dist) {
    // A ghost's acceleration lacks the pairs beyond this process's halo: the largest is the owned
    // fluid particles' (the other maxima and the minimum distance are over real pairs and densities).
    const std::vector<std::uint8_t>& ghost = dist->ghost_mask();
    double max_a2 = 0.0;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (ghost[i] || !particles_.is_fluid(i)) continue;
      double a2 = 0.0;
      for (int d = 0; d < Dim; ++d) a2 += particles_.acceleration[d][i] * particles_.acceleration[d][i];
      max_a2 = std::max(max_a2, a2);
    }
    summary.max_acceleration = std::sqrt(max_a2);
  }
  if (bodies_.any_moving())
    std::visit([&](const auto& kernel) {
      add_moving_wall_continuity(particles_, grid_, kernel, settings_.mass, bodies_.motion(),
                                 std::holds_alternative<DynamicWalls>(walls_), pair_threads);
    }, kernel_);
  std::visit([&](const auto& walls) { walls.after_rates(particles_, threads_, &bodies_.motion()); }, walls_);
  if (last && shifting_.coefficient > 0.0) {
    std::function<void(std::vector<double>&)> refresh;
    if (dist) refresh = [dist](std::vector<double>& divergence) { dist->refresh(divergence); };
    shift_.compute(particles_, grid_, kernel_, shifting_sums_, shifting_, terms_.fluid_mask.data(), pair_threads, refresh);
  }
  return summary;
}

template <int Dim>
void Solver<Dim>::add_external_acceleration(RateSummary& summary) {
  const std::vector<std::uint8_t>* ghost = distribution_ ? &distribution_->ghost_mask() : nullptr;
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < particles_.size(); ++i)
    if (particles_.is_fluid(i) && !(ghost != nullptr && i < ghost->size() && (*ghost)[i])) rows.push_back(i);
  std::vector<double> x(rows.size() * Dim), a(rows.size() * Dim, 0.0);
  for (std::size_t k = 0; k < rows.size(); ++k)
    for (int d = 0; d < Dim; ++d) x[k * Dim + d] = particles_.position[d][rows[k]];
  external_acceleration_(stage_time_, rows.size(), x.data(), a.data());
  double max_a2 = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t i = rows[k];
    double a2 = 0.0;
    for (int d = 0; d < Dim; ++d) {
      const double value = a[k * Dim + d];
      if (!std::isfinite(value))
        throw std::invalid_argument(fmt::format(
            "the body force gave a value that is not finite ({}) for particle id {} at t = {} s", value,
            particles_.id[i], stage_time_));
      particles_.acceleration[d][i] += value;
      a2 += particles_.acceleration[d][i] * particles_.acceleration[d][i];
    }
    max_a2 = std::max(max_a2, a2);
  }
  summary.max_acceleration = std::max(summary.max_acceleration, std::sqrt(max_a2));
}

template <int Dim>
std::size_t Solver<Dim>::set_fluid_velocities(std::span<const std::uint32_t> ids, std::span<const double> velocity) {
  if (velocity.size() != ids.size() * Dim)
    throw std::invalid_argument(fmt::format("{} velocities for {} particles; expected {} values ({} per particle)",
                                            velocity.size(), ids.size(), ids.size() * Dim, Dim));
  const std::vector<std::uint8_t>* ghost = distribution_ ? &distribution_->ghost_mask() : nullptr;
  std::uint32_t largest = 0;
  for (const std::uint32_t id : particles_.id) largest = std::max(largest, id);
  std::vector<std::int64_t> row(static_cast<std::size_t>(largest) + 1, -1);
  for (std::size_t i = 0; i < particles_.size(); ++i)
    if (!(ghost != nullptr && i < ghost->size() && (*ghost)[i])) row[particles_.id[i]] = static_cast<std::int64_t>(i);
  for (const double v : velocity)
    if (!std::isfinite(v)) throw std::invalid_argument(fmt::format("a velocity is not finite ({})", v));
  std::size_t set = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const std::uint32_t id = ids[k];
    if (id >= row.size() || row[id] < 0) {
      if (distribution_) continue;
      throw std::invalid_argument(
          fmt::format("particle id {} is no particle of the run (ids run from 0 to {})", id, largest));
    }
    const auto i = static_cast<std::size_t>(row[id]);
    if (!particles_.is_fluid(i))
      throw std::invalid_argument(fmt::format(
          "particle id {} is a wall particle; only the water's velocities can be set (a wall moves as its motion "
          "says)",
          id));
    for (int d = 0; d < Dim; ++d) particles_.velocity[d][i] = velocity[k * Dim + d];
    ++set;
  }
  clock_.rates_carried = false;
  swept_unhealthy_.reset();
  return set;
}

template <int Dim>
RateSummary Solver<Dim>::global(const RateSummary& r) const {
  return {reducer_->max(r.max_acceleration), reducer_->max(r.max_relative_speed), reducer_->max(r.max_density),
          reducer_->min(r.min_fluid_distance)};
}

template <int Dim>
double Solver<Dim>::choose_dt(const RateSummary& r) const {
  if (case_.fixed_dt > 0.0) return case_.fixed_dt;
  const double h = settings_.h;
  const TaitEos& eos = settings_.eos;
  const double max_sound_speed = eos.local_sound_speed(std::max(r.max_density, eos.rest_density));
  double dt = h / max_sound_speed;
  if (r.max_relative_speed > 0.0) dt = std::min(dt, h / r.max_relative_speed);
  if (r.max_acceleration > 0.0) dt = std::min(dt, std::sqrt(h / r.max_acceleration));
  return case_.cfl * dt;
}

template <int Dim>
typename Solver<Dim>::StepSize Solver<Dim>::step_size(const RateSummary& rates, double time_limit) const {
  const double dt = choose_dt(rates);
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::runtime_error(fmt::format("time step {} at t = {} s is not a positive finite number", dt, clock_.time));
  // Land exactly on the limit (an output time) rather than step past it.
  if (clock_.time + dt >= time_limit) return {time_limit - clock_.time, true};
  return {dt, false};
}

template <int Dim>
void Solver<Dim>::step(double time_limit) {
  const bool shepard_due = case_.shepard_every > 0 && clock_.step > 0 && clock_.step % case_.shepard_every == 0;
  has_saved_state_ = false;
  swept_unhealthy_.reset();
  if (case_.integrator == Integrator::leapfrog) {
    leapfrog_step(time_limit, shepard_due);
    return;
  }
  const bool euler = case_.integrator == Integrator::euler;
  const RateSummary rates = global(evaluate(shepard_due, 0u, euler));
  load_floating();
  min_particle_distance_ = rates.min_fluid_distance;
  saved_clock_ = clock_;
  const StepSize size = step_size(rates, time_limit);
  const double dt = size.dt;
  const double floor = settings_.eos.rest_density;
  if (case_.integrator == Integrator::predictor_corrector) {
    stop_wall_approach_before_drift(nullptr, 0.0);
    predictor_update(particles_, dt, floor, threads_);
    bodies_.each_floating([&](auto& body) { body.floating.predict(dt); });
    advance_walls(clock_.time + 0.5 * dt);
    has_saved_state_ = true;
    evaluate(false, field_role::step_start, true);
    load_floating();
    stop_wall_approach_before_drift(nullptr, 0.0);
    corrector_update(particles_, dt, floor, threads_);
    bodies_.each_floating([&](auto& body) { body.floating.correct(dt); });
  } else {
    particles_.position_start = particles_.position;
    particles_.velocity_start = particles_.velocity;
    particles_.density_start = particles_.density;
    has_saved_state_ = true;
    stop_wall_approach_before_drift(nullptr, 0.0);
    euler_update(particles_, dt, floor, threads_);
    bodies_.each_floating([&](auto& body) { body.floating.euler(dt); });
  }
  advance_walls(size.end(clock_.time, time_limit));
  finish_step(size, time_limit);
}

// The leapfrog (integrate/integrators.hpp): the rates of the state at the step's start, a(n) and D(n),
// are those its last evaluation left (carried, also through a checkpoint); a step that starts
// without them evaluates them first. The Shepard filter, when due, is applied at the step's first
// evaluation, as with the other integrators: the one at its end if the rates were carried (to the
// predicted densities, whose change the final kick keeps).
template <int Dim>
void Solver<Dim>::leapfrog_step(double time_limit, bool shepard_due) {
  if (!clock_.rates_carried) {
    clock_.rates = global(evaluate(shepard_due, 0u, false));
    load_floating();
    clock_.rates_carried = true;
    shepard_due = false;
  }
  min_particle_distance_ = clock_.rates.min_fluid_distance;
  saved_clock_ = clock_;
  const StepSize size = step_size(clock_.rates, time_limit);
  const double dt = size.dt;
  Particles<Dim>& p = particles_;
  // a(n), D(n) to the step-start fields, where the evaluation's reordering moves them with y(n).
  std::swap(p.acceleration, p.acceleration_start);
  std::swap(p.density_rate, p.density_rate_start);
  kick_drift_sweep(dt);
  bodies_.each_floating([&](auto& body) { body.floating.kick_drift(dt); });
  advance_walls(size.end(clock_.time, time_limit));
  has_saved_state_ = true;
  clock_.rates = global(evaluate(shepard_due, field_role::step_start | field_role::rates_start, true));
  load_floating();
  bodies_.each_floating([&](auto& body) { body.floating.final_kick(dt); });
  finish_step(size, time_limit, true);
}

// The leapfrog's stage 1 (integrate/integrators.hpp), each particle's drift velocity first stopped
// short of the walls (physics.wall_no_penetration), with the half kick a(n) dt/2 the drift adds: block
// by block (sweep_block), each stage a loop over a block still in cache from the stage before.
template <int Dim>
void Solver<Dim>::kick_drift_sweep(double dt) {
  Particles<Dim>& p = particles_;
  const double floor = settings_.eos.rest_density;
  const bool stop = case_.wall_no_penetration;
  const WallChecks<Dim> checks(solids_, case_.dx, &solid_reach_);
  parallel::for_chunks(static_cast<long>(p.size()), threads_, [&](long first, long last) {
    for (long begin = first; begin < last; begin += sweep_block) {
      const long end = std::min(last, begin + sweep_block);
      if (stop) checks.stop_approach(p, begin, end, &p.acceleration_start, 0.5 * dt);
      for (long i = begin; i < end; ++i) leapfrog_kick_drift_one(p, i, dt, floor);
    }
  });
}

// physics.wall_no_penetration: the velocity that moves the water next stops short of the walls
// (geometry/leaks.hpp); acceleration and tau give the part of the drift velocity the update adds.
template <int Dim>
void Solver<Dim>::stop_wall_approach_before_drift(const typename Particles<Dim>::template Vector<double>* acceleration,
                                                  double tau) {
  if (case_.wall_no_penetration) stop_wall_approach(particles_, solids_, case_.dx, acceleration, tau, threads_, &solid_reach_);
}

// What follows every integrator's update: the leapfrog's final kick (`final_kick`), the damping zone,
// the particle shift, the put-back of leaked particles, the outflow, the clock. The instability
// guard's count of the particles the step leaves is taken in the same sweep.
template <int Dim>
void Solver<Dim>::finish_step(const StepSize& size, double time_limit, bool final_kick) {
  const double dt = size.dt;
  const SweepCounts counts = sweep_after_update(dt, final_kick);
  strip_ghosts();
  clock_.leaks += counts.leaked;
  clock_.outflow += remove_outflow(counts.leaving);
  // A put-back particle moved (and its density is repaired at the next evaluation): the carried
  // rates are no longer those of the state. Every process decides alike.
  if (clock_.rates_carried && reducer_->sum(counts.leaked) > 0) clock_.rates_carried = false;
  clock_.time = size.end(clock_.time, time_limit);
  clock_.last_dt = dt;
  ++clock_.step;
  clock_.floating = bodies_.floating_state();
  absorb();
  // The absorbing pistons' walls moved after the sweep: the guard looks at them again.
  if (!bodies_.absorbs()) swept_unhealthy_ = counts.unhealthy;
}

// The stages in turn on each block of particles (sweep_block): the final kick, the damping, the
// shift (stopped short of the walls), the put-back, then whether each particle leaves an open tank
// and, if it stays, whether the guard would stop the run for it. Every stage is each particle's own,
// so the sweep gives what the stages would one after the other over all particles, with the
// particles read from memory once. A ghost (another process's particle, stripped after the sweep) is
// updated like the others but not put back or counted.
template <int Dim>
typename Solver<Dim>::SweepCounts Solver<Dim>::sweep_after_update(double dt, bool final_kick) {
  Particles<Dim>& p = particles_;
  const double floor = settings_.eos.rest_density;
  const bool damps = case_.damps(), shifts = shifting_.coefficient > 0.0;
  const bool stop_shift = shifts && case_.wall_no_penetration, open = !case_.tank_lid;
  const DampingZone<Dim> zone = damps ? DampingZone<Dim>::of(case_) : DampingZone<Dim>{};
  const WallChecks<Dim> checks(solids_, case_.dx, &solid_reach_);
  const std::array<double*, Dim> shift = shifts ? shift_.shift_velocity_data() : std::array<double*, Dim>{};
  const std::uint8_t* ghost =
      distribution_ && distribution_->has_ghosts() ? distribution_->ghost_mask().data() : nullptr;
  const Reach r = reach();
  SweepCounts total;
  parallel::for_chunks(static_cast<long>(p.size()), threads_, [&](long first, long last) {
    SweepCounts part;
    for (long begin = first; begin < last; begin += sweep_block) {
      const long end = std::min(last, begin + sweep_block);
      if (final_kick)
        for (long i = begin; i < end; ++i) leapfrog_final_kick_one(p, i, dt, floor);
      if (damps) damp(p, zone, dt, begin, end);
      if (shifts) {
        if (stop_shift) checks.stop_shift(p, shift, begin, end);
        shift_.apply(p, dt, begin, end);
      }
      part.leaked += checks.put_back(p, begin, end, ghost);
      // Two loops, so that the one without ghosts (every run on one process) vectorises.
      std::int64_t leaving = 0, unhealthy = 0;
      if (ghost == nullptr) {
        for (long i = begin; i < end; ++i) {
          const bool gone = open & leaves(static_cast<std::size_t>(i), r);
          leaving += gone;
          unhealthy += !gone & !healthy(static_cast<std::size_t>(i), r);
        }
      } else {
        for (long i = begin; i < end; ++i) {
          const bool gone = open & leaves(static_cast<std::size_t>(i), r);
          leaving += !ghost[i] & gone;
          unhealthy += !ghost[i] & !gone & !healthy(static_cast<std::size_t>(i), r);
        }
      }
      part.leaving += leaving;
      part.unhealthy += unhealthy;
    }
#pragma omp atomic
    total.leaked += part.leaked;
#pragma omp atomic
    total.leaving += part.leaving;
#pragma omp atomic
    total.unhealthy += part.unhealthy;
  });
  return total;
}

// The floating bodies take the water's force and moment on their particles in the state just
// evaluated (summed over the processes), and their accelerations follow.
template <int Dim>
void Solver<Dim>::load_floating() {
  if (!bodies_.floats()) return;
  // A contact as stiff as the water at a particle: rho0 c0^2 dx^(Dim - 2).
  const double stiffness = case_.rest_density * case_.sound_speed * case_.sound_speed * std::pow(case_.dx, Dim - 2);
  const auto contacts = bodies_.contact_loads(solids_, case_.walls.size(), case_.dx, stiffness);
  bodies_.each_floating([&](auto& body) {
    const BodyLoad load = body_load(body.id);
    Vec3 force{};
    for (int d = 0; d < Dim; ++d) force[d] = load.force[d];
    body.floating.set_load(force, load.moment, contacts[body.id].force, contacts[body.id].moment);
  });
  clock_.floating = bodies_.floating_state();
}

// The absorbing pistons observe the surface in front of them at the step's end and set their
// correction's rate until the next; their walls' velocities at this time follow it. Their state is
// part of the clock, so that a checkpoint, and the guard's return to a step's start, keep it.
template <int Dim>
void Solver<Dim>::absorb() {
  if (!bodies_.absorbs()) return;
  bodies_.absorb(clock_.time, [&](const Vec<Dim>& foot) { return kernel_surface<Dim>(*this, foot); });
  clock_.absorbers = bodies_.absorber_state();
  advance_walls(clock_.time);
}

// Water that went over the walls of an open tank and fell beyond their reach is gone: it is removed
// (with its step-start state and carried rates, so that the guard's return to the step's start and
// the leapfrog's next kick apply to the particles that remain). The carried rates of the others stay
// those of the state at the step's end, of which the removed particles were part. The indices of the
// cell grid no longer hold after the compaction: for_each_range_in_box scans everything until the
// next evaluation bins again.
template <int Dim>
std::int64_t Solver<Dim>::remove_outflow(std::int64_t leaving_here) {
  if (case_.tank_lid) return 0;
  if (leaving_here > 0) {
    const Reach r = reach();
    const std::size_t n = particles_.size();
    std::vector<std::uint8_t> gone(n, 0);
    for (std::size_t i = 0; i < n; ++i) gone[i] = leaves(i, r);
    particles_.erase(gone);
    grid_binned_ = false;
  }
  return reducer_->sum(leaving_here);
}

template <int Dim>
typename Solver<Dim>::Reach Solver<Dim>::reach() const {
  constexpr int up = Dim - 1;
  const double margin = wall_layers(case_) * case_.dx + 4.0 * settings_.h;
  const Vec3 size = case_.tank_size();
  Reach r;
  for (int d = 0; d < Dim; ++d) {
    r.lower[d] = -margin;
    r.upper[d] = size[d] + margin;
  }
  r.top = size[up] + (case_.tank_lid ? margin : 10.0 * std::max(size[up], margin));
  if (tank_swept_) {  // a moving tank carries its water within the box its walls sweep
    for (int d = 0; d < Dim; ++d) {
      r.lower[d] = std::min(r.lower[d], tank_swept_->first[d] - margin);
      r.upper[d] = std::max(r.upper[d], tank_swept_->second[d] + margin);
    }
    r.top = std::max(r.top, tank_swept_->second[up] + (case_.tank_lid ? margin : r.top - size[up]));
  }
  return r;
}

template <int Dim>
typename Solver<Dim>::BodyLoad Solver<Dim>::body_load(std::uint8_t body) const {
  const Particles<Dim>& p = particles_;
  const BodyState<Dim>& state = bodies_.motion().state[body];
  Vec3 centre{}, force{}, moment{};
  for (int d = 0; d < Dim; ++d) centre[d] = state.centre[d] + state.displacement[d];
  // Before the first evaluation there are no rates: no load.
  const bool rated = p.acceleration[0].size() == p.size() && evaluations_ > 0;
  // Within a step (a floating body's load) the evaluation's ghosts are still mixed in: other
  // processes' particles, whose loads their owners count.
  const std::uint8_t* ghost =
      distribution_ && distribution_->has_ghosts() ? distribution_->ghost_mask().data() : nullptr;
  for (std::size_t i = 0; rated && i < p.owned(); ++i) {
    if (p.body[i] != body || (ghost && ghost[i])) continue;
    Vec3 f{}, r{};
    for (int d = 0; d < Dim; ++d) {
      f[d] = settings_.mass * p.acceleration[d][i];
      r[d] = p.position[d][i] - centre[d];
    }
    force = force + f;
    moment = moment + Vec3{r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
  }
  BodyLoad load;
  for (int d = 0; d < Dim; ++d) load.force[d] = reducer_->sum(force[d]);
  for (int d = 0; d < 3; ++d) load.moment[d] = reducer_->sum(moment[d]);
  return load;
}

template <int Dim>
Diagnostics Solver<Dim>::diagnostics() const {
  Diagnostics d;
  d.time = clock_.time;
  d.step = clock_.step;
  d.dt = clock_.last_dt;
  d.leaks = clock_.leaks;
  d.outflow = clock_.outflow;
  d.min_density = std::numeric_limits<double>::infinity();
  d.max_density = -std::numeric_limits<double>::infinity();
  const double m = settings_.mass;
  const Particles<Dim>& p = particles_;
  std::int64_t fluid = 0, wall = 0, not_finite = 0;
  for (std::size_t i = 0; i < p.owned(); ++i) {
    const double rho = p.density[i];
    d.min_density = std::min(d.min_density, rho);
    d.max_density = std::max(d.max_density, rho);
    bool finite = std::isfinite(rho);
    if (!p.is_fluid(i)) {
      ++wall;
      not_finite += !finite;
      continue;
    }
    ++fluid;
    double v2 = 0.0, g_dot_x = 0.0;
    for (int k = 0; k < Dim; ++k) {
      v2 += p.velocity[k][i] * p.velocity[k][i];
      g_dot_x += settings_.gravity[k] * p.position[k][i];
      finite = finite && std::isfinite(p.position[k][i]) && std::isfinite(p.velocity[k][i]);
    }
    not_finite += !finite;
    d.max_speed = std::max(d.max_speed, std::sqrt(v2));
    d.kinetic_energy += 0.5 * m * v2;
    d.potential_energy -= m * g_dot_x;
  }
  const Reducer& all = *reducer_;
  d.fluid_particles = static_cast<std::size_t>(all.sum(fluid));
  d.wall_particles = static_cast<std::size_t>(all.sum(wall));
  d.all_finite = all.sum(not_finite) == 0;
  d.min_density = all.min(d.min_density);
  d.max_density = all.max(d.max_density);
  d.max_speed = all.max(d.max_speed);
  d.kinetic_energy = all.sum(d.kinetic_energy);
  d.potential_energy = all.sum(d.potential_energy);
  d.total_mass = m * static_cast<double>(d.fluid_particles);
  d.min_particle_distance = min_particle_distance_;
  return d;
}

template <int Dim>
Health Solver<Dim>::check_health(std::size_t max_reported) const {
  const Particles<Dim>& p = particles_;
  const double rho0 = settings_.eos.rest_density;
  const Reach r = reach();
  auto problem = [&](std::size_t i) -> const char* {
    bool finite = std::isfinite(p.density[i]);
    for (int d = 0; d < Dim; ++d) finite = finite && std::isfinite(p.position[d][i]) && std::isfinite(p.velocity[d][i]);
    if (!finite) return "not finite";
    if (!in_reach(i, r) && p.is_fluid(i)) return "far outside the tank";
    const double rho = p.density[i];
    if (!(rho > 0.5 * rho0 && rho < 2.0 * rho0)) return "density outside (0.5, 2) rho0";
    return nullptr;
  };
  const long n = static_cast<long>(p.owned());
  const std::int64_t bad = reducer_->sum(
      swept_unhealthy_ ? *swept_unhealthy_ : parallel::count<std::int64_t>(n, threads_, [&](long i) -> std::int64_t {
        return healthy(static_cast<std::size_t>(i), r) ? 0 : 1;
      }));
  Health health;
  health.offending = static_cast<std::size_t>(bad);
  // A moving wall is placed by its law, the same on every process; one the set-up's samples of its
  // motion did not see leave the tank is stopped here.
  health.wall_outside = bodies_.outside_tank(case_.tank_size(), case_.tank_lid);
  if (bad == 0) return health;
  // The offenders described are this process's (the count is everyone's).
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < p.owned(); ++i)
    if (problem(i) != nullptr) rows.push_back(i);
  std::sort(rows.begin(), rows.end(), [&](std::size_t a, std::size_t b) { return p.id[a] < p.id[b]; });
  const double support2 = 4.0 * settings_.h * settings_.h;
  for (std::size_t k = 0; k < rows.size() && k < max_reported; ++k) {
    const std::size_t i = rows[k];
    Offender o;
    o.id = p.id[i];
    o.dimension = Dim;
    for (int d = 0; d < Dim; ++d) {
      o.position[d] = p.position[d][i];
      o.velocity[d] = p.velocity[d][i];
    }
    o.density = p.density[i];
    o.reason = problem(i);
    for (std::size_t j = 0; j < p.size(); ++j) {
      double r2 = 0.0;
      for (int d = 0; d < Dim; ++d) {
        const double delta = p.position[d][i] - p.position[d][j];
        r2 += delta * delta;
      }
      if (j != i && r2 < support2) ++o.neighbours;
    }
    health.first.push_back(o);
  }
  return health;
}

// The state at the start of the step (after the reordering of its first evaluation) lives in the
// step-start arrays, which the predictor-corrector and the leapfrog fill anyway; forward Euler does
// not use them, so step() fills them there too. No extra memory; restore_saved_state() copies them
// back, and for the leapfrog the rates a(n), D(n) it carried into the step (the reordering moved all
// of them alike), so that a restart from the state saved then continues as the step did.
template <int Dim>
void Solver<Dim>::restore_saved_state() {
  strip_ghosts();
  swept_unhealthy_.reset();
  if (!has_saved_state_) return;
  Particles<Dim>& p = particles_;
  p.position = p.position_start;
  p.velocity = p.velocity_start;
  p.density = p.density_start;
  if (case_.integrator == Integrator::leapfrog) {
    p.acceleration = p.acceleration_start;
    p.density_rate = p.density_rate_start;
  }
  std::fill(p.needs_density_repair.begin(), p.needs_density_repair.end(), 0);
  // The particles that left an open tank in the step stay removed (also from the step-start state),
  // and counted.
  const std::int64_t outflow = clock_.outflow;
  clock_ = saved_clock_;
  clock_.outflow = outflow;
  bodies_.set_absorber_state(clock_.absorbers);
  bodies_.set_floating_state(clock_.floating);
  advance_walls(clock_.time);  // the walls' bodies and solids (their particles were restored above)
}

}  // namespace sluice
