// The sluice command line: lists the commands (each in its own file) and maps errors to exit codes.
#include <iostream>

#include "sluice/app/commands.hpp"
#include "sluice/case/params.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/npz.hpp"

using namespace sluice;

int main(int argc, char** argv) {
  CLI::App cli{"sluice: a fast, validated SPH solver for free-surface water flows (dam breaks, sloshing, waves)."};
  cli.set_version_flag("--version", std::string("sluice ") + SLUICE_VERSION);
  cli.require_subcommand(1);
  cli.footer("Run `sluice <command> --help` for a command's options. With no case, `sluice run` runs the default dam break.");

  const std::vector<app::Command> commands = {
      app::add_run_command(cli),
      app::add_cases_command(cli),
      app::add_init_command(cli),
  };

  try {
    cli.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return cli.exit(e);
  } catch (const CLI::ParseError& e) {
    cli.exit(e);
    return app::exit_bad_input;
  }

  try {
    for (const auto& c : commands)
      if (c.cli->parsed()) return c.run();
  } catch (const CaseError& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return app::exit_bad_input;
  } catch (const app::BadInput& e) {
    std::cerr << "sluice: error: " << e.what() << "\n";
    return app::exit_bad_input;
  } catch (const std::exception& e) {  // IoError, FormatError, a failed run
    std::cerr << "sluice: error: " << e.what() << "\n";
    return app::exit_failure;
  }
  return 0;
}
