#include "sluice/io/run_outputs.hpp"

#include <fmt/format.h>

#include <optional>
#include <utility>
#include <vector>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/schedule.hpp"

namespace sluice {

namespace {

constexpr const char* diagnostics_header =
    "time,step,dt,max_speed,min_density,max_density,kinetic_energy,potential_energy,total_energy,total_mass,"
    "leaks,outflow,min_particle_distance,wall_time\n";

std::string diagnostics_row(const Diagnostics& d, double wall_seconds) {
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3f}\n", d.time, d.step, d.dt, d.max_speed,
                     d.min_density, d.max_density, d.kinetic_energy, d.potential_energy,
                     d.kinetic_energy + d.potential_energy, d.total_mass, d.leaks, d.outflow, d.min_particle_distance,
                     wall_seconds);
}

template <class Write>
void write_streamed(const std::filesystem::path& path, Write&& write) {
  AtomicFile file(path);
  write([&](std::string_view bytes) { file.write(bytes); });
  file.commit();
}

std::string frame_stem(std::int64_t index) { return fmt::format("{}/frame_{:06}", output_files::frames_dir, index); }

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

}  // namespace

void prepare_output_dir(const std::filesystem::path& dir, const std::string& case_name, bool fresh) {
  create_directories_or_throw(dir);
  for (const char* sub : {".", output_files::frames_dir, output_files::probes_dir, output_files::bodies_dir})
    remove_stale_temp_files(dir / sub);
  if (fresh) remove_previous_outputs(dir, case_name);
}

RunOutputs::RunOutputs(const Simulation& sim, std::filesystem::path dir, bool fresh, double wall_before,
                       const Communicator* comm)
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

void RunOutputs::write_frame(std::int64_t index, const Simulation& sim, double wall_seconds) {
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

void RunOutputs::sample_probes(const Simulation& sim) {
  probes_.sample(sim);
  bodies_.sample(sim);
}

void RunOutputs::write_checkpoint_file(const Simulation& sim, double wall_seconds) {
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

// Frames 0..K at the regular times up to the checkpoint were written before it and are kept, with
// their diagnostics rows and .pvd entries. A frame written at the checkpoint time when that was not a
// regular frame time (the end of the previous run, or Ctrl-C) is dropped: the continued run writes
// that frame number at its regular time, as the run that never stopped did.
void RunOutputs::keep_until_checkpoint(double checkpoint_time) {
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

}  // namespace sluice
