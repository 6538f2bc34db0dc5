// The processes of a run, as the solver sees them: who this process is, the reductions, and moving
// bytes between processes. One process has no Communicator at all (the solver's code for one process
// is the code of today); several processes get the MPI one (mpi/mpi_communicator.hpp), which is the
// only code that includes <mpi.h>. Every function is collective: all processes call it, in the same
// order, or the run hangs.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sluice/core/reduce.hpp"

namespace sluice {

// An axis-aligned box of the domain decomposition (3 components; a 2D run uses the first two).
struct DomainBox {
  std::array<double, 3> lower{};
  std::array<double, 3> upper{};
};

// What a process that failed tells the others (Communicator::fail).
struct Failure {
  int process = 0;      // the process that failed (the first, when several failed together)
  int processes = 1;    // how many processes the run has
  int kind = 0;         // the caller's classification of the error, passed along as is
  std::string message;  // that process's message

  // "process 1 of 4: <message>"
  [[nodiscard]] std::string describe() const {
    return "process " + std::to_string(process) + " of " + std::to_string(processes) + ": " + message;
  }
};

// Thrown by a collective call when another process has failed: the call does not take place, and every
// process that was waiting learns of the failure at once (Communicator::fail).
class ProcessFailure : public std::runtime_error {
 public:
  explicit ProcessFailure(Failure f) : std::runtime_error(f.describe()), failure_(std::move(f)) {}
  [[nodiscard]] const Failure& failure() const { return failure_; }

 private:
  Failure failure_;
};

class Communicator {
 public:
  virtual ~Communicator() = default;
  [[nodiscard]] virtual int rank() const = 0;
  [[nodiscard]] virtual int size() const = 0;
  [[nodiscard]] bool is_root() const { return rank() == 0; }
  // Sums, maxima and minima over all processes.
  [[nodiscard]] virtual const Reducer& reducer() const = 0;

  // send[r] goes to process r (send.size() == size(); send[rank()] is handed back as is); returns
  // received[r], the bytes process r sent to this one.
  [[nodiscard]] virtual std::vector<std::string> exchange(const std::vector<std::string>& send) const = 0;
  // The root (rank 0) receives every process's part, in rank order; the others receive nothing.
  [[nodiscard]] virtual std::vector<std::string> gather(const std::string& part) const = 0;
  // Every process receives the root's bytes (the argument is ignored elsewhere).
  [[nodiscard]] virtual std::string broadcast(const std::string& from_root) const = 0;

  // Recursive coordinate bisection of weighted points (each process passes its own; `dimension` 2 or
  // 3 components of each point are used) into size() boxes of nearly equal weight, one per process:
  // box r is the region process r owns. The boxes tile all of space: the outer faces are at
  // -infinity and +infinity, and a point on a shared face belongs to the box above it (lower <= x <
  // upper). Every process receives all the boxes.
  [[nodiscard]] virtual std::vector<DomainBox> partition(int dimension, const std::vector<std::array<double, 3>>& points,
                                                         const std::vector<double>& weights) const = 0;

  // A process that meets an error between collective calls (in its own work, where the others cannot
  // see it) reports it here, instead of making its next collective call. Every collective call starts
  // by checking for such a report: a process waiting there throws ProcessFailure instead, with this
  // Failure. So every process learns of the failure at the same point of the sequence of collective
  // calls, and all can go on together (to save the last good state). Returns the Failure the others
  // receive: the first process's, when several fail together. An error inside a collective call (out
  // of memory for its buffers) cannot be reported so, and stops every process (abort).
  [[nodiscard]] virtual Failure fail(const std::string& message, int kind) const = 0;

  // Stops every process at once with this message on standard error and the exit status (for a
  // process that fails where the others cannot learn of it: they are waiting for it in a collective).
  [[noreturn]] virtual void abort(const std::string& message, int status) const = 0;
};

}  // namespace sluice
