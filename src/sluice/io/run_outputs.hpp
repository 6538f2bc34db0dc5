// What a run writes into its output directory as it goes: the frames (.npz, .vtu and the .pvd
// index), the diagnostics rows, the probe and body series, and checkpoints. Each frame's files are
// written whole; diagnostics rows, .pvd entries and probe samples are appended to their files, so a
// frame costs the same at any point of a run.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "sluice/core/communicator.hpp"
#include "sluice/io/append_file.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/bodies.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/probes.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

// Files a run writes into its output directory.
namespace output_files {
inline constexpr const char* frames_dir = "frames";
inline constexpr const char* diagnostics = "diagnostics.csv";
inline constexpr const char* checkpoint = "checkpoint.bin";
inline constexpr const char* probes_dir = "probes";
inline constexpr const char* bodies_dir = "bodies";
inline constexpr const char* summary = "summary.txt";
}  // namespace output_files

// Output files are written by the root process alone. `write` runs there; with several processes, an
// error there is sent to every process, and each throws it (IoError), so that all stop together (the
// others would otherwise wait for the root at the next step).
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

// The output directory made ready (root only): created, temporary files of a killed run removed, and
// for a fresh run (not a restart) the outputs of an earlier run there removed.
void prepare_output_dir(const std::filesystem::path& dir, const std::string& case_name, bool fresh);

class RunOutputs {
 public:
  // For a restart (not `fresh`), the rows, entries and frames on disk after the checkpoint's time are
  // dropped: the continued run writes them again.
  RunOutputs(const Simulation& sim, std::filesystem::path dir, bool fresh, double wall_before, const Communicator* comm);

  // Frame `index` of the state now, with its diagnostics row and the probe rows sampled so far.
  // Collective: every process's particles, on the root.
  void write_frame(std::int64_t index, const Simulation& sim, double wall_seconds);
  void sample_probes(const Simulation& sim);  // after every step; collective
  // What a restart keeps is made durable first, then the checkpoint written whole. Collective.
  void write_checkpoint_file(const Simulation& sim, double wall_seconds);

  [[nodiscard]] int frames_written() const { return frames_written_; }

 private:
  void keep_until_checkpoint(double checkpoint_time);

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

}  // namespace sluice
