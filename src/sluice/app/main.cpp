// The sluice command line: lists the commands (each in its own file) and maps errors to exit codes.
#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>

#include "sluice/app/commands.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/suggest.hpp"
#include "sluice/core/thread_waiting.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/run.hpp"
#include "sluice/mpi/mpi_communicator.hpp"
#include "sluice/physics/simd_target.hpp"

using namespace sluice;

namespace {

// No command, an option where the command belongs, or an unknown command: CLI11 would only say "A
// subcommand is required". The exit status if the first argument is not a command.
std::optional<int> refuse_missing_command(int argc, char** argv, const std::vector<app::Command>& commands) {
  std::vector<std::string> names;
  for (const auto& c : commands) names.push_back(c.cli->get_name());
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  if (argc == 1) {
    std::cerr << "sluice: error: no command given; expected one of: " << list
              << "\nRun `sluice --help` for the commands.\n";
    return app::exit_bad_input;
  }
  const std::string first = argv[1];
  if (first[0] == '-' && first != "-h" && first != "--help" && first != "--version") {
    std::cerr << "sluice: error: unknown option '" << first << "'; expected a command (" << list
              << "), --help or --version\nRun `sluice --help` for the commands.\n";
    return app::exit_bad_input;
  }
  if (first[0] != '-' && std::find(names.begin(), names.end(), first) == names.end()) {
    const auto near = closest_match(first, names);
    std::cerr << "sluice: error: unknown command '" << first << "'; "
              << (near ? "did you mean '" + *near + "'?" : "expected one of: " + list)
              << "\nRun `sluice --help` for the commands.\n";
    return app::exit_bad_input;
  }
  return std::nullopt;
}

// Prints an error as "sluice: error: ..." and gives its exit status. In an MPI run, an error every
// process meets alike (io/run.hpp: fails_alike; bad command-line input) is printed once, by the root;
// any other stops every process at once (the others may be waiting for this one), with the message of
// the process that failed.
int report(const std::exception& e, int status) {
  const std::string what = error_text(e);
  const Communicator* world = app::processes();
  if (world != nullptr && !fails_alike(e) && dynamic_cast<const app::BadInput*>(&e) == nullptr)
    world->abort(fmt::format("process {} of {}: {}", world->rank(), world->size(), what), status);
  if (world == nullptr || world->is_root()) std::cerr << "sluice: error: " << what << "\n";
  return status;
}

// Runs the command given, with every error as "sluice: error: ..." and its exit status.
int run_parsed(const std::vector<app::Command>& commands) {
  try {
    for (const auto& c : commands)
      if (c.cli->parsed()) return c.run();
  } catch (const CaseError& e) {
    return report(e, app::exit_bad_input);
  } catch (const app::BadInput& e) {
    return report(e, app::exit_bad_input);
  } catch (const view::ViewError& e) {  // a port in use
    return report(e, app::exit_bad_input);
  } catch (const std::exception& e) {  // IoError, FormatError, a failed run
    return report(e, app::exit_failure);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  restart_with_brief_spinning(argv);
  // Past a file-size limit (ulimit -f) a write then fails with EFBIG and is reported like a full disk,
  // instead of the process being killed by SIGXFSZ.
  std::signal(SIGXFSZ, SIG_IGN);
  // Under mpirun, one of several processes (sluice run spreads the particles over them); MPI is not
  // touched otherwise.
  std::unique_ptr<MpiSession> mpi;
  try {
    mpi = start_mpi_if_launched(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return app::exit_failure;
  }
  app::set_processes(mpi ? mpi->world() : nullptr);
  CLI::App cli{"sluice: a fast, validated SPH solver for free-surface water flows (dam breaks, sloshing, waves)."};
  cli.set_version_flag("--version", [] {
    std::string targets;
    for (const auto& t : available_simd_targets()) targets += (targets.empty() ? "" : ", ") + t;
    return std::string("sluice ") + SLUICE_VERSION + "\npair loop: " + simd_target() + " (this CPU runs " + targets + ")";
  });
  cli.require_subcommand(1);
  cli.footer("Run `sluice <command> --help` for a command's options. With no case, `sluice run` runs the default dam break.");

  const std::vector<app::Command> commands = {
      app::add_run_command(cli),
      app::add_cases_command(cli),
      app::add_init_command(cli),
      app::add_keys_command(cli),
      app::add_render_command(cli),
      app::add_analyze_command(cli),
      app::add_convergence_command(cli),
      app::add_validate_command(cli),
      app::add_view_command(cli),
  };
  if (const auto status = refuse_missing_command(argc, argv, commands)) return *status;

  try {
    cli.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    // Same form as every other error: "sluice: error: ..." on stderr, exit status 2.
    std::string help = "sluice --help";
    for (const auto& c : commands)
      if (c.cli->get_name() == argv[1]) help = "sluice " + c.cli->get_name() + " --help";
    if (mpi == nullptr || mpi->rank() == 0)
      std::cerr << "sluice: error: " << e.what() << "\nRun `" << help << "` for the options.\n";
    return app::exit_bad_input;
  }
  return run_parsed(commands);
}
