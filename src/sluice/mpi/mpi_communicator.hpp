// The processes of a run started by mpirun (Open MPI): the session that starts and stops MPI, and the
// Communicator of core/communicator.hpp over MPI, with Zoltan's recursive coordinate bisection for
// the domain boxes. This header and its .cpp are the only code that sees <mpi.h> and zoltan.h: the
// MPI and Zoltan types stay behind a pointer, so the rest of sluice builds without their headers.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sluice/core/communicator.hpp"

namespace sluice {

// All the processes of MPI_COMM_WORLD (through a duplicate, so that our messages never meet another
// library's). Needs MPI started (MpiSession). Every function is collective, as in Communicator; an
// invalid argument is reported on every process alike (the same exception everywhere) whenever the
// processes can learn of it, so that none is left waiting for the others.
class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator();
  ~MpiCommunicator() override;
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  [[nodiscard]] int rank() const override;
  [[nodiscard]] int size() const override;
  // Sums of doubles are added in rank order, maxima and minima are exact: the results are the same
  // bits on every process and in every run with the same number of processes. A NaN part makes the
  // maximum and the minimum NaN everywhere; payload_of_max counts NaN as the largest value.
  [[nodiscard]] const Reducer& reducer() const override;

  // Messages travel with MPI's int counts: a part, or all the bytes a process sends or receives in
  // one call, beyond INT_MAX bytes throws std::length_error on every process (nothing is truncated).
  // exchange() throws std::invalid_argument when send.size() != size() (on that process only).
  [[nodiscard]] std::vector<std::string> exchange(const std::vector<std::string>& send) const override;
  [[nodiscard]] std::vector<std::string> gather(const std::string& part) const override;
  [[nodiscard]] std::string broadcast(const std::string& from_root) const override;

  // Zoltan's RCB, one part per process (part r is box r), deterministic. Points at the same coordinate
  // stay on one side of a cut, and each cut is halfway between the nearest points on its two sides: a
  // lattice is cut between two of its rows, and the boxes (lower <= x < upper) give every point the
  // part Zoltan balanced it into, to within one row of points per cut. A point can only be on a face
  // when two points are closer than the spacing of doubles; it then belongs to the box above.
  // Weights must be finite and >= 0 (Zoltan keeps them as floats); when they are all zero, every point
  // counts as 1. Identical points cannot be split: all of them land in one box, and some boxes are
  // empty (lower == upper in a component, possibly both infinite). With no points at all, box 0 is
  // all of space. Invalid input (dimension other than 2 or 3 or not the same on all processes,
  // weights.size() != points.size(), a coordinate that is not finite or beyond 1e300 in magnitude, a
  // negative or non-finite weight) throws std::invalid_argument on every process, naming the first
  // process at fault.
  [[nodiscard]] std::vector<DomainBox> partition(int dimension, const std::vector<std::array<double, 3>>& points,
                                                 const std::vector<double>& weights) const override;

  [[nodiscard]] Failure fail(const std::string& message, int kind) const override;

  // "sluice: error: <message>" on standard error, then MPI_Abort of every process with `status`.
  [[noreturn]] void abort(const std::string& message, int status) const override;

 private:
  // A collective call's body, run after the check for a failed process (fail()). Out of memory inside
  // it stops every process: the others are in this call, waiting for this process's part.
  template <class F>
  auto collective(F&& body) const;

  struct State;
  std::unique_ptr<State> state_;
};

// True when a launcher started this process as one of an MPI job: Open MPI's mpirun/mpiexec
// (OMPI_COMM_WORLD_SIZE), or a PMI or PMIx launcher (PMI_SIZE, PMIX_RANK: MPICH's hydra, Slurm).
[[nodiscard]] bool launched_by_mpi();

// MPI for the life of the program: started by start_mpi_if_launched(), stopped (MPI_Finalize) by the
// destructor. At most one per process, since MPI starts only once.
class MpiSession {
 public:
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  // The processes of the run when there are 2 or more; nullptr for one process, which then runs the
  // serial code (mpirun -np 1 is the same as no mpirun).
  [[nodiscard]] const Communicator* world() const { return world_.get(); }
  [[nodiscard]] int rank() const { return rank_; }
  [[nodiscard]] int size() const { return size_; }
  // How long MPI_Init_thread took, in seconds.
  [[nodiscard]] double init_seconds() const { return init_seconds_; }

 private:
  friend std::unique_ptr<MpiSession> start_mpi_if_launched(int& argc, char**& argv);
  MpiSession(int rank, int size, double init_seconds);

  int rank_ = 0;
  int size_ = 1;
  double init_seconds_ = 0.0;
  std::unique_ptr<MpiCommunicator> world_;
};

// Starts MPI (MPI_Init_thread, MPI_THREAD_FUNNELED: OpenMP threads inside a process, MPI called from
// the main thread only) when launched_by_mpi(); otherwise returns nullptr without touching MPI, and
// the program runs as it always has. Throws std::logic_error when MPI was started before, and
// std::runtime_error when MPI cannot give the funneled thread level. MPI may take its own options out
// of argc and argv.
[[nodiscard]] std::unique_ptr<MpiSession> start_mpi_if_launched(int& argc, char**& argv);

// The processes of MPI_COMM_WORLD when MPI was started by the program that hosts sluice (mpi4py in a
// Python interpreter under mpirun) and there are 2 or more of them; nullptr otherwise (MPI not
// started, or one process). Throws std::runtime_error when MPI gives less than the funneled thread
// level. It must be gone before MPI is stopped.
[[nodiscard]] std::unique_ptr<MpiCommunicator> world_of_started_mpi();

}  // namespace sluice
