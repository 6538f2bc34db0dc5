#include "sluice/simulation.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "sluice/case/release_gate.hpp"
#include "sluice/core/heap.hpp"

namespace sluice {

namespace {

std::variant<Solver<2>, Solver<3>> make_solver(const Case& c, int threads, const Communicator* comm) {
  if (c.dimension == 3) return Solver<3>(c, threads, comm);
  if (c.dimension == 2) return Solver<2>(c, threads, comm);
  throw std::invalid_argument(fmt::format("domain.dimension = {}: expected 2 or 3", c.dimension));
}

std::variant<Solver<2>, Solver<3>> resume_solver(const Case& c, AnyParticles particles, Clock clock, int threads,
                                                  const Communicator* comm) {
  const int dim = std::holds_alternative<Particles<3>>(particles) ? 3 : 2;
  if (dim != c.dimension)
    throw std::invalid_argument(
        fmt::format("saved particles are {}D but the case is {}D (domain.dimension = {})", dim, c.dimension,
                    c.dimension));
  if (dim == 3) return Solver<3>(c, std::get<Particles<3>>(std::move(particles)), clock, threads, comm);
  return Solver<2>(c, std::get<Particles<2>>(std::move(particles)), clock, threads, comm);
}

}  // namespace

// The solver runs the case with its release gate made a wall (case/release_gate.hpp): config() and a
// checkpoint hold the expanded case.
// The steps keep the memory they free (core/heap.hpp); the set-up before them does not, so that its
// large temporaries are given back and do not leave gaps in the heap.
Simulation::Simulation(const Case& c, int threads, const Communicator* comm)
    : solver_(make_solver(with_release_gate(c), threads, comm)) {
  keep_freed_memory();
}

Simulation::Simulation(const Case& c, AnyParticles particles, Clock clock, int threads, const Communicator* comm)
    : solver_(resume_solver(with_release_gate(c), std::move(particles), clock, threads, comm)) {
  keep_freed_memory();
}

}  // namespace sluice
