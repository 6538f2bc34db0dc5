#include "sluice/io/run.hpp"

#include <fmt/format.h>

#include <new>

#include "sluice/case/case_error.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/runner.hpp"
#include "sluice/physics/simd_target.hpp"

namespace sluice {

bool fails_alike(const std::exception& e) {
  return dynamic_cast<const CaseError*>(&e) != nullptr || dynamic_cast<const IoError*>(&e) != nullptr ||
         dynamic_cast<const FormatError*>(&e) != nullptr || dynamic_cast<const InstabilityError*>(&e) != nullptr ||
         dynamic_cast<const RunFailure*>(&e) != nullptr;
}

std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr)
    return "out of memory (std::bad_alloc); use a coarser domain.dx, or spread the run over more processes and "
           "machines";
  const std::string what = e.what();
  return what.empty() ? "an error without a message" : what;
}

RunResult run_case(const Case& c, const RunOptions& options, std::ostream& log) {
  Runner runner(c, options, log);
  return runner.run();
}

namespace {

// "threads     2" or, after the run came down to fewer on a busy machine,
// "threads     2 for 80 % of the steps, 1 for 20 % (fewer were faster while the machine was busy)".
std::string format_threads(const RunResult& r) {
  const auto& steps = r.thread_steps;
  const std::string each = r.processes > 1 ? " in each process" : "";
  if (steps.empty()) return "";
  if (steps.size() == 1) return fmt::format("  threads     {}{}\n", steps[0].first, each);
  std::int64_t total = 0;
  for (const auto& [threads, n] : steps) total += n;
  std::string s = "  threads     ";
  for (std::size_t k = 0; k < steps.size(); ++k)
    s += fmt::format("{}{} for {:.0f} % of the steps", k > 0 ? ", " : "", steps[k].first,
                     100.0 * static_cast<double>(steps[k].second) / static_cast<double>(std::max<std::int64_t>(total, 1)));
  return s + each + " (fewer were faster while the machine was busy)\n";
}

}  // namespace

std::string format_summary(const RunResult& r) {
  const Diagnostics& d = r.final;
  std::string s;
  s += fmt::format("sluice {}: case '{}' {} at t = {:.4f} s\n", SLUICE_VERSION, r.case_name,
                  r.interrupted ? "stopped on request" : "finished", d.time);
  s += fmt::format("  particles   {} ({} fluid, {} wall)\n", r.particles, d.fluid_particles, d.wall_particles);
  s += fmt::format("  steps       {} ({} force evaluation{} per step), {} in this run\n", d.step,
                   r.force_evaluations_per_step, r.force_evaluations_per_step == 1 ? "" : "s", r.steps_this_run);
  if (r.processes > 1) {
    s += fmt::format("  processes   {} (MPI; the particles split among them by recursive coordinate bisection)\n",
                     r.processes);
    const double steps = static_cast<double>(std::max<std::int64_t>(r.steps_this_run, 1));
    s += fmt::format("  exchanges   {:.3f} MB per step between processes, {:.2f} ms per step ({:.1f} % of the loop); "
                     "ghosts {:.1f} % of the particles\n",
                     r.bytes_exchanged / steps * 1e-6, r.exchange_seconds / steps * 1e3,
                     r.loop_seconds > 0 ? 100.0 * r.exchange_seconds / r.loop_seconds : 0.0, 100.0 * r.ghost_share);
  }
  s += format_threads(r);
  s += fmt::format("  wall time   {:.2f} s for this run\n", r.wall_seconds);
  s += fmt::format("  loop time   {:.3f} s stepping (without set-up and final output)\n", r.loop_seconds);
  s += fmt::format("  speed       {:.2f} M particle-steps/s, {:.2f} M particle-evaluations/s\n",
                   r.particle_steps_per_second * 1e-6,
                   r.particle_steps_per_second * r.force_evaluations_per_step * 1e-6);
  s += fmt::format("  pair loop   {} (the instruction set it ran on), {} precision\n", simd_target(),
                   r.single_precision_pairs ? "single" : "double");
  s += fmt::format("  leaks       {} (fluid particles put back from inside a wall)\n", d.leaks);
  if (d.outflow > 0)
    s += fmt::format("  outflow     {} (fluid particles that went over the open tank's walls, removed)\n", d.outflow);
  s += fmt::format("  density     min {:.2f}, max {:.2f} kg/m^3 (rho0 = {})\n", d.min_density, d.max_density,
                   r.rest_density);
  s += fmt::format("  max speed   {:.3f} m/s (c0 = {} m/s)\n", d.max_speed, r.sound_speed);
  s += fmt::format("  all finite  {}\n", d.all_finite ? "yes" : "NO");
  s += fmt::format("  output      {} ({} frames written)\n", r.output_dir.string(), r.frames_written);
  for (const std::string& n : r.notes) s += fmt::format("  note        {}\n", n);
  return s;
}

}  // namespace sluice
