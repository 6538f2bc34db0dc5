// sluice run, sluice cases, sluice init.
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "sluice/app/commands.hpp"
#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/case_template.hpp"
#include "sluice/case/load.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/run.hpp"
#include "sluice/physics/simd_target.hpp"

namespace fs = std::filesystem;

namespace sluice::app {

namespace {

std::atomic<bool> stop_requested{false};
const Communicator* world = nullptr;

extern "C" void on_signal(int signal) {
  stop_requested.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C stops at once
}

struct RunArgs {
  std::string case_arg, output, restart, render_field, simd;
  std::vector<std::string> sets;
  int threads = 0;
  bool fixed_threads = false;
  bool quiet = false;
  bool view = false;
  int port = 8050;
  std::string host = "127.0.0.1";
};

int run(const RunArgs& a) {
  if (!a.render_field.empty()) check_render_field(a.render_field);
  if (!a.simd.empty()) {
    try {
      use_simd_target(a.simd);
    } catch (const std::invalid_argument& e) {
      throw BadInput(fmt::format("--simd: {}", e.what()));
    }
  }
  Case c;
  RunOptions options;
  options.comm = world;
  const bool root = world == nullptr || world->is_root();
  // By default the cores are shared among the processes of an MPI run (on one machine).
  options.threads = a.threads > 0 ? a.threads : std::max(1, omp_get_num_procs() / (world ? world->size() : 1));
  options.adapt_threads = !a.fixed_threads;
  if (!a.restart.empty()) {
    if (!a.case_arg.empty())
      throw BadInput("--restart continues the case stored in the checkpoint; give no case with it");
    options.restart = a.restart;
    options.restart_overrides = a.sets;  // only time.end is accepted (checked by run_case)
    std::error_code ec;
    if (!fs::is_regular_file(a.restart, ec)) {
      const fs::path dir = fs::path(a.restart).parent_path();
      const bool run_there = fs::is_directory(dir / output_files::frames_dir, ec);
      throw IoError(fmt::format(
          "{}: no such checkpoint file; {}a run writes its checkpoint every output.checkpoint_wall_interval seconds "
          "of wall time (20 by default), at each output.checkpoint_interval of simulated time, at its end and when "
          "stopped with Ctrl-C, SIGTERM or SIGHUP. Without one, run the case again from its start",
          a.restart,
          run_there ? fmt::format("{} holds frames of a run that stopped before writing one (killed within its "
                                  "first checkpoint interval, or with checkpoints turned off); ",
                                  (dir.empty() ? fs::path(".") : dir).string())
                    : std::string()));
    }
    options.output_dir = a.output.empty() ? fs::path(a.restart).parent_path() : fs::path(a.output);
    if (options.output_dir.empty()) options.output_dir = ".";
  } else {
    c = a.case_arg.empty() ? *load_builtin_case("dam_break") : case_from_argument(a.case_arg);
    apply_overrides(c, a.sets);
    options.output_dir = a.output.empty() ? fs::path("out") / c.name : fs::path(a.output);
  }
  options.progress = a.quiet ? RunOptions::Progress::none
                             : (::isatty(::fileno(stderr)) ? RunOptions::Progress::tty : RunOptions::Progress::lines);
  options.stop_requested = &stop_requested;
  options.command = options.restart ? "sluice run --restart" : "sluice run";
  // Ctrl-C, a kill's SIGTERM and a closed terminal or SSH session's SIGHUP all stop the run after the
  // current step, with its outputs and a checkpoint written.
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGHUP, on_signal);

  // The live view: the page served from the output directory as the run writes it, its controls
  // reaching the run between steps (the root process serves it).
  view::Controls controls;
  controls.stop = &stop_requested;
  std::unique_ptr<view::ViewServer> server;
  if (a.view && root) {
    view::ServerOptions o = view_options(a.host, a.port);
    o.controls = &controls;
    try {  // the reference data are extras: a restart whose checkpoint cannot be read fails below anyway
      o.overlays = view_overlays(options.restart ? read_checkpoint(*options.restart).config : c);
    } catch (const std::exception&) {
    }
    server = std::make_unique<view::ViewServer>(options.output_dir, o);
    std::cerr << fmt::format("sluice: watch the run at {}\n", server->address());
  }
  options.pause_requested = &controls.pause;
  options.checkpoint_requested = &controls.checkpoint;
  if (!a.quiet && root) {
    const std::string per = world != nullptr ? fmt::format(" on each of {} processes", world->size()) : "";
    if (options.restart) std::cerr << fmt::format("sluice: restarting from {}\n", a.restart);
    else
      std::cerr << fmt::format("sluice: running '{}' into {} with {} thread{}{}\n", c.name, options.output_dir.string(),
                               options.threads, options.threads == 1 ? "" : "s", per);
  }
  const RunResult r = run_case(c, options, std::cerr);
  if (!root) return r.interrupted ? exit_interrupted : 0;
  std::cout << format_summary(r);
  if (!a.render_field.empty() && !r.interrupted) render_after_run(options.output_dir, a.render_field, a.quiet);
  return r.interrupted ? exit_interrupted : 0;
}

}  // namespace

void set_processes(const Communicator* comm) { world = comm; }
const Communicator* processes() { return world; }

Case case_from_argument(const std::string& name_or_path) {
  std::error_code ec;
  // A built-in name, unless a file of that name exists (a directory of that name, such as the output
  // of `sluice run dam_break -o dam_break`, does not hide the built-in case).
  if (!fs::exists(name_or_path, ec) || fs::is_directory(name_or_path, ec)) {
    if (auto c = load_builtin_case(name_or_path)) return *c;
  }
  return load_case_file(name_or_path);
}

Command add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  auto* cmd = app.add_subcommand("run", "Run a case (a .toml file or a built-in case name; default: dam_break).");
  cmd->add_option("case", args->case_arg, "Case file (.toml) or built-in case name (see `sluice cases`)");
  cmd->add_option("-o,--output", args->output, "Output directory (default: out/<case name>)");
  cmd->add_option("--set", args->sets, "Override a case key, e.g. --set domain.dx=0.1 (repeatable)")
      ->allow_extra_args(false);
  cmd->add_option("--threads", args->threads,
                  "Threads to use (per process under mpirun; default: all cores, shared among the processes); the "
                  "run steps with fewer while fewer are faster, as on a machine busy with other work")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--fixed-threads", args->fixed_threads,
                "Step with --threads threads throughout, also while fewer would be faster (to measure a thread "
                "count's speed)");
  cmd->add_option("--restart", args->restart,
                  "Continue from a checkpoint file (e.g. out/dam_break/checkpoint.bin); with it, --set may only "
                  "change time.end");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress line");
  cmd->add_flag("--view", args->view,
                "Serve a live view of the run in the browser (the address, with the token for its controls, is "
                "printed)");
  cmd->add_option("--port", args->port, "With --view: the port to listen on (default 8050; 0: any free port)")
      ->check(CLI::Range(0, 65535));
  cmd->add_option("--host", args->host,
                  "With --view: the address to listen on (default 127.0.0.1; another requires the token for every "
                  "request)");
  cmd->add_option("--simd", args->simd,
                  "Instruction set of the pair loop: auto (the best this CPU runs, the default) or one that "
                  "`sluice --version` lists, e.g. AVX2 on an AVX-512 machine, to compare them");
  cmd->add_option("--render", args->render_field,
                  "At the end, draw an animated GIF of this field into the output directory (vx, vy, speed, "
                  "pressure, density; see `sluice render`)");
  return {cmd, [args] { return run(*args); }};
}

Command add_cases_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("cases", "List the built-in cases.");
  return {cmd, [] {
            for (const auto& b : builtin_cases())
              std::cout << fmt::format("{:<16} {}\n", b.name, load_builtin_case(b.name)->description);
            return 0;
          }};
}

Command add_init_command(CLI::App& app) {
  struct InitArgs {
    std::string path = "case.toml", from = "water_column";
    bool force = false;
  };
  auto args = std::make_shared<InitArgs>();
  auto* cmd = app.add_subcommand("init", "Write a fully commented case file to edit and run.");
  cmd->add_option("file", args->path, "File to write (default: case.toml)");
  cmd->add_option("--from", args->from,
                  "Built-in case to start from (default: water_column, a collapsing column with the default settings, "
                  "which are the ones validation chose; see `sluice cases`)");
  cmd->add_flag("--force", args->force, "Overwrite the file if it exists");
  return {cmd, [args] {
            const auto c = load_builtin_case(args->from);
            if (!c) throw BadInput(fmt::format("--from {}: no built-in case of that name; see `sluice cases`", args->from));
            std::error_code ec;
            if (fs::is_directory(args->path, ec))
              throw BadInput(fmt::format("{}: is a directory; expected the name of the case file to write, e.g. {}",
                                         args->path, (fs::path(args->path) / "case.toml").string()));
            if (fs::exists(args->path, ec) && !args->force)
              throw BadInput(fmt::format("{}: already exists; use --force to overwrite it", args->path));
            write_file_atomic(args->path, case_template(*c));
            std::cout << fmt::format("wrote {} (from the built-in case '{}'); run it with: sluice run {}\n", args->path,
                                     args->from, args->path);
            return 0;
          }};
}

}  // namespace sluice::app
