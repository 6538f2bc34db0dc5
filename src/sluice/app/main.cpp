// The sluice command line: a thin layer over the case loader and the run loop.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "sluice/case/params.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/run.hpp"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

// Exit codes: 0 success, 1 the run failed (I/O, a damaged file, an unstable run), 2 bad input
// (command line or case file), 130 stopped by Ctrl-C (after writing its outputs).
constexpr int exit_failure = 1;
constexpr int exit_bad_input = 2;
constexpr int exit_interrupted = 130;

std::atomic<bool> stop_requested{false};

extern "C" void on_signal(int signal) {
  stop_requested.store(true);
  std::signal(signal, SIG_DFL);  // a second Ctrl-C stops at once
}

struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

Case resolve_case(const std::string& name_or_path) {
  if (name_or_path.empty()) return *load_builtin_case("dam_break");
  std::error_code ec;
  if (!fs::exists(name_or_path, ec)) {
    if (auto c = load_builtin_case(name_or_path)) return *c;
  }
  return load_case_file(name_or_path);
}

int command_run(const std::string& case_arg, const std::string& output, const std::vector<std::string>& sets,
                int threads, const std::string& restart, bool quiet) {
  Case c;
  RunOptions options;
  options.threads = threads > 0 ? threads : omp_get_num_procs();
  if (!restart.empty()) {
    if (!case_arg.empty() || !sets.empty())
      throw BadInput("--restart continues the case stored in the checkpoint; give no case file or --set with it");
    options.restart = restart;
    std::error_code ec;
    if (!fs::is_regular_file(restart, ec)) throw IoError(fmt::format("{}: no such checkpoint file", restart));
    options.output_dir = output.empty() ? fs::path(restart).parent_path() : fs::path(output);
    if (options.output_dir.empty()) options.output_dir = ".";
  } else {
    c = resolve_case(case_arg);
    for (const auto& s : sets) apply_override(c, s);
    options.output_dir = output.empty() ? fs::path("out") / c.name : fs::path(output);
  }
  options.progress = quiet ? RunOptions::Progress::none
                           : (::isatty(::fileno(stderr)) ? RunOptions::Progress::tty : RunOptions::Progress::lines);
  options.stop_requested = &stop_requested;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  if (!quiet) {
    if (options.restart) std::cerr << fmt::format("sluice: restarting from {}\n", restart);
    else std::cerr << fmt::format("sluice: running '{}' into {} with {} thread{}\n", c.name,
                                  options.output_dir.string(), options.threads, options.threads == 1 ? "" : "s");
  }
  const RunResult r = run_case(c, options, std::cerr);
  std::cout << format_summary(r);
  return r.interrupted ? exit_interrupted : 0;
}

int command_cases() {
  for (const auto& b : builtin_cases()) {
    const auto c = load_builtin_case(b.name);
    std::cout << fmt::format("{:<16} {}\n", b.name, c->description);
  }
  return 0;
}

int command_init(const std::string& path, const std::string& from, bool force) {
  const auto c = load_builtin_case(from);
  if (!c) throw BadInput(fmt::format("--from {}: no built-in case of that name; see `sluice cases`", from));
  std::error_code ec;
  if (fs::exists(path, ec) && !force)
    throw BadInput(fmt::format("{}: already exists; use --force to overwrite it", path));
  write_file_atomic(path, case_template(*c));
  std::cout << fmt::format("wrote {} (from the built-in case '{}'); run it with: sluice run {}\n", path, from, path);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sluice: a fast, validated SPH solver for free-surface water flows (dam breaks, sloshing, waves)."};
  app.set_version_flag("--version", std::string("sluice ") + SLUICE_VERSION);
  app.require_subcommand(1);
  app.footer("Run `sluice <command> --help` for a command's options. With no case, `sluice run` runs the default dam break.");

  std::string case_arg, output, restart;
  std::vector<std::string> sets;
  int threads = 0;
  bool quiet = false;
  auto* run = app.add_subcommand("run", "Run a case (a .toml file or a built-in case name; default: dam_break).");
  run->add_option("case", case_arg, "Case file (.toml) or built-in case name (see `sluice cases`)");
  run->add_option("-o,--output", output, "Output directory (default: out/<case name>)");
  run->add_option("--set", sets, "Override a case key, e.g. --set domain.dx=0.1 (repeatable)")->allow_extra_args(false);
  run->add_option("--threads", threads, "Threads to use (default: all cores)")->check(CLI::Range(1, 1024));
  run->add_option("--restart", restart, "Continue from a checkpoint file (e.g. out/dam_break/checkpoint.bin)");
  run->add_flag("-q,--quiet", quiet, "No progress line");

  auto* cases = app.add_subcommand("cases", "List the built-in cases.");

  std::string init_path = "case.toml", init_from = "dam_break";
  bool force = false;
  auto* init = app.add_subcommand("init", "Write a fully commented case file to edit and run.");
  init->add_option("file", init_path, "File to write (default: case.toml)");
  init->add_option("--from", init_from, "Built-in case to start from (default: dam_break)");
  init->add_flag("--force", force, "Overwrite the file if it exists");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return exit_bad_input;
  }

  try {
    if (run->parsed()) return command_run(case_arg, output, sets, threads, restart, quiet);
    if (cases->parsed()) return command_cases();
    if (init->parsed()) return command_init(init_path, init_from, force);
  } catch (const CaseError& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const BadInput& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return exit_bad_input;
  } catch (const IoError& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return exit_failure;
  } catch (const FormatError& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return exit_failure;
  } catch (const std::exception& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return exit_failure;
  }
  return 0;
}
