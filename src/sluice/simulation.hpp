// A Simulation is a value: the solver of a case in the case's dimension (a Solver<2> or a Solver<3>,
// chosen at run time), behind one interface for the run loop, the writers and the tests. Two of them
// can live side by side (no global state).
#pragma once

#include <limits>
#include <variant>

#include "sluice/solver/solver.hpp"

namespace sluice {

// Particles of either dimension, as a checkpoint holds them.
using AnyParticles = std::variant<Particles<2>, Particles<3>>;

class Simulation {
 public:
  // Builds the particles of a case (setup) and starts at t = 0; with a communicator of several
  // processes, each holds its region's share (Solver).
  explicit Simulation(const Case& c, int threads = 1, const Communicator* comm = nullptr);
  // Continues from a saved state (restart); the particles' dimension must be the case's.
  Simulation(const Case& c, AnyParticles particles, Clock clock, int threads = 1, const Communicator* comm = nullptr);

  // The solver itself, for code written for any dimension: f(solver) with a Solver<2> or Solver<3>.
  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit(std::forward<F>(f), solver_);
  }
  template <class F>
  decltype(auto) visit(F&& f) {
    return std::visit(std::forward<F>(f), solver_);
  }

  // Advances one time step; a step that would pass time_limit ends exactly on it.
  void step(double time_limit = std::numeric_limits<double>::infinity()) {
    visit([&](auto& s) { s.step(time_limit); });
  }
  void restore_saved_state() {
    visit([](auto& s) { s.restore_saved_state(); });
  }
  [[nodiscard]] bool has_saved_state() const {
    return visit([](const auto& s) { return s.has_saved_state(); });
  }

  [[nodiscard]] int dimension() const { return std::holds_alternative<Solver<3>>(solver_) ? 3 : 2; }
  [[nodiscard]] const Clock& clock() const { return visit([](const auto& s) -> const Clock& { return s.clock(); }); }
  [[nodiscard]] double time() const { return clock().time; }
  [[nodiscard]] const Case& config() const {
    return visit([](const auto& s) -> const Case& { return s.config(); });
  }
  // Particles on all processes.
  [[nodiscard]] std::size_t particle_count() const {
    return visit([](const auto& s) { return s.particle_count(); });
  }
  // The process that writes the outputs (always, with one process).
  [[nodiscard]] bool is_root() const {
    return visit([](const auto& s) { return s.is_root(); });
  }
  [[nodiscard]] double particle_mass() const { return visit([](const auto& s) { return s.particle_mass(); }); }
  [[nodiscard]] double smoothing_length() const { return visit([](const auto& s) { return s.smoothing_length(); }); }
  [[nodiscard]] const TaitEos& eos() const { return visit([](const auto& s) -> const TaitEos& { return s.eos(); }); }
  [[nodiscard]] std::size_t removed_near_coincident() const {
    return visit([](const auto& s) { return s.removed_near_coincident(); });
  }
  [[nodiscard]] const std::vector<std::string>& setup_notes() const {
    return visit([](const auto& s) -> const std::vector<std::string>& { return s.setup_notes(); });
  }
  [[nodiscard]] int force_evaluations_per_step() const {
    return visit([](const auto& s) { return s.force_evaluations_per_step(); });
  }
  // Force evaluations made since the solver was built (Solver::force_evaluations).
  [[nodiscard]] std::int64_t force_evaluations() const {
    return visit([](const auto& s) { return s.force_evaluations(); });
  }
  [[nodiscard]] int threads() const { return visit([](const auto& s) { return s.threads(); }); }
  void set_threads(int threads) {
    visit([threads](auto& s) { s.set_threads(threads); });
  }
  [[nodiscard]] Diagnostics diagnostics() const { return visit([](const auto& s) { return s.diagnostics(); }); }
  // The instability guard (Solver::check_health).
  [[nodiscard]] Health check_health(std::size_t max_reported = 5) const {
    return visit([&](const auto& s) { return s.check_health(max_reported); });
  }

  // The solver of a known dimension (throws std::bad_variant_access for the other).
  template <int Dim>
  [[nodiscard]] const Solver<Dim>& solver() const {
    return std::get<Solver<Dim>>(solver_);
  }
  template <int Dim>
  [[nodiscard]] const Particles<Dim>& particles() const {
    return solver<Dim>().particles();
  }

 private:
  std::variant<Solver<2>, Solver<3>> solver_;
};

}  // namespace sluice
