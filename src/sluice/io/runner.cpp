#include "sluice/io/runner.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <thread>

#include "sluice/case/case_error.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/directory_lock.hpp"
#include "sluice/io/progress.hpp"
#include "sluice/io/run_checks.hpp"
#include "sluice/io/run_outputs.hpp"
#include "sluice/io/schedule.hpp"
#include "sluice/io/thread_governor.hpp"

namespace sluice {

namespace {

using steady = std::chrono::steady_clock;

double seconds_since(steady::time_point t0) { return std::chrono::duration<double>(steady::now() - t0).count(); }

// Where the last good state is: in the output directory's files, or (a run without outputs) the
// simulation's state itself.
std::string where_saved(const Simulation& good, std::int64_t frame, const std::filesystem::path& dir) {
  if (dir.empty())
    return fmt::format("The simulation is back at the last good state (t = {:.6g} s, step {}).", good.time(),
                       good.clock().step);
  return fmt::format("The last good state (t = {:.6g} s, step {}) is saved as {}/frame_{:06} and {} in {}.",
                     good.time(), good.clock().step, output_files::frames_dir, frame, output_files::checkpoint,
                     dir.string());
}

std::string describe_instability(const std::string& failure, const Health& health, double time, std::int64_t step,
                                 const Simulation& good, std::int64_t frame, const std::filesystem::path& dir) {
  if (failure.empty() && health.offending == 0 && !health.wall_outside.empty())
    return fmt::format("the run stopped at t = {:.6g} s (step {}): {}: a moving wall must stay inside the tank until "
                       "time.end = {:.6g} s.\n{}",
                       time, step, health.wall_outside, good.config().end_time, where_saved(good, frame, dir));
  std::string m = fmt::format("the run became unstable at t = {:.6g} s (step {}): ", time, step);
  m += failure.empty() ? describe_offenders(health) : failure + "\n";
  m += where_saved(good, frame, dir) + "\n";
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

// The simulation a run starts with, checked, and its output directory made ready and locked.
Start start_run(const Case& requested, const RunOptions& options, std::optional<DirectoryLock>& lock) {
  if (!options.restart) check_memory(requested, options.comm);
  Start start = options.restart ? start_from_checkpoint(options)
                                : Start{std::make_unique<Simulation>(requested, options.threads, options.comm)};
  check_start(*start.sim, options.restart.value_or(std::filesystem::path()));
  check_output_plan(*start.sim);
  if (options.output_dir.empty()) return start;
  const double bytes = planned_frame_bytes(*start.sim);
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
  return start;
}

}  // namespace

// A run from its start to its end (or a stop): the steps, and the outputs due after each.
struct Runner::Impl {
  Impl(const Case& c, RunOptions opts, std::ostream& log)
      : options_(std::move(opts)), wall_start_(steady::now()), fresh_(!options_.restart) {
    Start start = start_run(c, options_, lock_);
    sim_ = std::move(start.sim);
    if (!options_.output_dir.empty()) {
      outputs_.emplace(*sim_, options_.output_dir, fresh_, start.wall_before, options_.comm);
      checkpoint_wall_interval_ = sim_->config().checkpoint_wall_interval;
    }
    schedule_.emplace(sim_->config(), sim_->time());
    progress_.emplace(sim_->is_root() ? options_.progress : ProgressMode::none, log, sim_->time(), schedule_->end(),
                      sim_->particle_count());
    particles_ = sim_->particle_count();
    outflow_ = sim_->clock().outflow;
    // Every process must have the same counts to try, as they decide together; a run whose processes
    // were given different thread counts keeps them.
    const Reducer& all = options_.comm != nullptr ? options_.comm->reducer() : serial_reducer();
    const auto threads = static_cast<double>(options_.threads);
    const bool adapt = options_.adapt_threads && all.min(threads) == all.max(threads);
    governor_.emplace(options_.threads, adapt, [reducer = &all](double v) { return reducer->max(v); });
    sim_->set_threads(governor_->threads());
    // The set-up's notes now, before a long run, and again in the summary.
    if (sim_->is_root() && options_.progress != ProgressMode::none) {
      for (const std::string& n : sim_->setup_notes()) log << "sluice: note: " << n << "\n";
      if (checkpoint_wall_interval_ > 0.0)
        log << fmt::format("sluice: a checkpoint every {:g} s of wall time (output.checkpoint_wall_interval) into {}; "
                           "after a kill, `sluice run --restart {}` continues from it\n",
                           checkpoint_wall_interval_, (options_.output_dir / output_files::checkpoint).string(),
                           (options_.output_dir / output_files::checkpoint).string());
    }
    sim_->visit([&](const auto& solver) {
      if (const auto* d = solver.distribution()) {
        bytes_before_ = d->bytes_sent();
        exchange_seconds_before_ = d->exchange_seconds();
      }
    });
    guarded([&] {
      if (fresh_ && outputs_) {
        outputs_->sample_probes(*sim_);
        outputs_->write_frame(0, *sim_, 0.0);
      }
    });
    loop_start_ = steady::now();
    last_checkpoint_ = loop_start_;
  }

  bool step(double limit) {
    if (stopped_ || sim_->time() >= schedule_->end()) return false;
    return guarded([&] {
      for (Request request = requested(); request != Request::none; request = requested()) {
        if (request == Request::stop) {
          interrupted_ = true;
          stopped_ = true;
          return false;
        }
        if (request == Request::checkpoint) {
          write_checkpoint();
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // paused
      }
      guarded_step(limit);
      write_due_outputs();
      progress_->update(*sim_, steps_, seconds_since(loop_start_));
      return true;
    });
  }

  RunResult finish() {
    if (finished_) throw std::logic_error("the run has finished already");
    return guarded([&] {
      progress_->update(*sim_, steps_, seconds_since(loop_start_), true);
      progress_->finish();
      if (outputs_) {
        if (!frame_is_current_) outputs_->write_frame(schedule_->next_frame(), *sim_, wall());
        outputs_->write_checkpoint_file(*sim_, wall());
      }
      finished_ = true;
      stopped_ = true;
      RunResult r = result();
      if (outputs_)
        on_root(options_.comm,
                [&] { write_file_atomic(options_.output_dir / output_files::summary, format_summary(r)); });
      return r;
    });
  }

  [[nodiscard]] double wall() const { return seconds_since(wall_start_); }

  // Calls f; an error stops the run. An error every process met alike is reported as it is. With one
  // process, so is an error outside a step (writing the outputs): there is no other state to save
  // than the one that failed. Otherwise the last good state is saved and one error thrown for all
  // (stop_failed).
  template <class F>
  auto guarded(F&& f) -> decltype(f()) {
    try {
      return f();
    } catch (const ProcessFailure& e) {
      stopped_ = true;
      stop_failed(e.failure());  // another process failed: this one learnt of it in a collective call
    } catch (const std::exception& e) {
      stopped_ = true;
      if (fails_alike(e) || (options_.comm == nullptr && !mid_step_)) throw;
      const int kind = dynamic_cast<const std::runtime_error*>(&e) != nullptr ? kUnstable : kFailed;
      const std::string what = error_text(e);
      stop_failed(options_.comm != nullptr ? options_.comm->fail(what, kind) : Failure{0, 1, kind, what});
    }
  }

  // What a step's end asks for, on any process, so that every process does it after the same step:
  // a stop (Ctrl-C, SIGTERM, SIGHUP), which writes a checkpoint; a checkpoint, because
  // output.checkpoint_wall_interval seconds of wall time have passed since the last or the live
  // view asked for one; or a pause, asked for by the live view (one reduction for all: the most
  // pressing wins, and a pause is asked again after a checkpoint).
  enum class Request { none = 0, pause = 1, checkpoint = 2, stop = 3 };
  [[nodiscard]] Request requested() {
    Request here = Request::none;
    if (options_.stop_requested != nullptr && options_.stop_requested->load()) here = Request::stop;
    else if ((checkpoint_wall_interval_ > 0.0 && seconds_since(last_checkpoint_) >= checkpoint_wall_interval_) ||
             (options_.checkpoint_requested != nullptr && options_.checkpoint_requested->exchange(false)))
      here = Request::checkpoint;
    else if (options_.pause_requested != nullptr && options_.pause_requested->load())
      here = Request::pause;
    if (options_.comm == nullptr) return here;
    return static_cast<Request>(std::lround(options_.comm->reducer().max(static_cast<double>(here))));
  }

  // Writes a checkpoint now (the state at the end of the last step), and times it: the interval
  // between the periodic ones is stretched to 50 times that, so that they cost at most 2 % of the run.
  void write_checkpoint() {
    if (!outputs_) return;
    const auto start = steady::now();
    outputs_->write_checkpoint_file(*sim_, wall());
    last_checkpoint_ = steady::now();
    const double seconds = seconds_since(start);
    if (checkpoint_wall_interval_ > 0.0)
      checkpoint_wall_interval_ = std::max(sim_->config().checkpoint_wall_interval, 50.0 * seconds);
  }

  // The instability guard: if the step leaves any particle non-finite, far outside the tank or at an
  // absurd density, go back to the state before it, save that and stop. (A step that throws, which
  // the solver does when the time step is not finite, is stopped the same way: guarded, stop_failed.)
  void guarded_step(double limit) {
    mid_step_ = true;
    const auto start = steady::now();
    sim_->step(std::min(schedule_->step_limit(), limit));
    mid_step_ = false;
    const Health health = sim_->check_health();
    governor_->stepped(seconds_since(start));
    sim_->set_threads(governor_->threads());
    if (!health.ok()) {
      const double bad_time = sim_->time();
      const std::int64_t bad_step = sim_->clock().step;
      sim_->restore_saved_state();
      save_last_good_state();
      throw InstabilityError(describe_instability("", health, bad_time, bad_step, *sim_, schedule_->next_frame(),
                                                  options_.output_dir));
    }
    ++steps_;
    particle_steps_ += static_cast<double>(particles_);
    if (sim_->clock().outflow != outflow_) {  // the same on every process: a collective call or none
      outflow_ = sim_->clock().outflow;
      particles_ = sim_->particle_count();
    }
    frame_is_current_ = false;
    if (outputs_) outputs_->sample_probes(*sim_);
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
                                                  bad_step, *sim_, schedule_->next_frame(), options_.output_dir));
    if (!outputs_)
      throw RunFailure(fmt::format("{}: {}\n{}", who, f.message, where_saved(*sim_, 0, options_.output_dir)));
    throw RunFailure(fmt::format(
        "{}: {}\nThe last good state (t = {:.6g} s, step {}) is saved as {}/frame_{:06} and {} in {}; `sluice run "
        "--restart {}` continues from it.",
        who, f.message, sim_->time(), sim_->clock().step, output_files::frames_dir, schedule_->next_frame(),
        output_files::checkpoint, options_.output_dir.string(),
        (options_.output_dir / output_files::checkpoint).string()));
  }

  void save_last_good_state() {
    if (outputs_) {
      outputs_->write_frame(schedule_->next_frame(), *sim_, wall());
      outputs_->write_checkpoint_file(*sim_, wall());
    }
    progress_->finish();
  }

  void write_due_outputs() {
    const double t = sim_->time();
    if (schedule_->frame_due(t)) {
      if (outputs_) outputs_->write_frame(schedule_->next_frame(), *sim_, wall());
      frame_is_current_ = true;
      schedule_->frame_written(t);
    }
    if (schedule_->checkpoint_due(t)) {
      write_checkpoint();
      schedule_->checkpoint_written(t);
    }
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
    r.frames_written = outputs_ ? outputs_->frames_written() : 0;
    for (const auto& share : governor_->shares()) r.thread_steps.emplace_back(share.threads, share.steps);
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

  RunOptions options_;
  steady::time_point wall_start_;
  steady::time_point loop_start_;
  bool fresh_;
  // Held until the runner is gone: no second run writes into this directory meanwhile.
  std::optional<DirectoryLock> lock_;
  std::unique_ptr<Simulation> sim_;
  std::optional<RunOutputs> outputs_;  // none without an output directory
  std::optional<Schedule> schedule_;
  std::optional<ProgressLine> progress_;
  std::optional<ThreadGovernor> governor_;
  std::int64_t steps_ = 0;
  // On all processes: constant through a run but for the water that leaves an open tank (outflow_).
  std::size_t particles_ = 0;
  std::int64_t outflow_ = 0;
  double particle_steps_ = 0.0;  // the particles of each step of this run, summed
  bool mid_step_ = false;        // in Simulation::step
  double bytes_before_ = 0.0, exchange_seconds_before_ = 0.0;  // the set-up's exchanges
  bool interrupted_ = false;
  bool stopped_ = false;
  bool finished_ = false;
  double checkpoint_wall_interval_ = 0.0;  // 0: none while running
  steady::time_point last_checkpoint_;
  // A restart's state at the checkpoint time is already on disk (or, at a non-frame time, needs no frame).
  bool frame_is_current_ = true;
};

Runner::Runner(const Case& c, RunOptions options, std::ostream& log)
    : impl_(std::make_unique<Impl>(c, std::move(options), log)) {}
Runner::~Runner() = default;

const Simulation& Runner::simulation() const { return *impl_->sim_; }
Simulation& Runner::simulation() { return *impl_->sim_; }
double Runner::end_time() const { return impl_->schedule_->end(); }
bool Runner::at_end() const { return impl_->sim_->time() >= impl_->schedule_->end(); }
bool Runner::stopped() const { return impl_->stopped_; }
bool Runner::writes_outputs() const { return impl_->outputs_.has_value(); }

bool Runner::step(double limit) { return impl_->step(limit); }

bool Runner::advance_to(double t) {
  while (impl_->sim_->time() < std::min(t, impl_->schedule_->end()))
    if (!impl_->step(t)) return false;
  return !impl_->stopped_;
}

RunResult Runner::finish() { return impl_->finish(); }

RunResult Runner::run() {
  advance_to(end_time());
  return finish();
}

}  // namespace sluice
