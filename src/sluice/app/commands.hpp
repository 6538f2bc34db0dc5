// Each `sluice <command>` lives in its own file and registers itself with the CLI through one of
// these functions; main.cpp lists them and maps errors to exit codes.
#pragma once

#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/communicator.hpp"
#include "sluice/view/view_server.hpp"

namespace sluice::app {

// Exit codes: 0 success, 1 the run failed (I/O, a damaged file, an unstable run), 2 bad input
// (command line or case file), 130 stopped by Ctrl-C (after writing its outputs).
inline constexpr int exit_failure = 1;
inline constexpr int exit_bad_input = 2;
inline constexpr int exit_interrupted = 130;

// Bad command-line input that CLI11 cannot check by itself (exit code 2).
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Command {
  CLI::App* cli;             // the subcommand, to test whether it was given
  std::function<int()> run;  // runs it after parsing; throws on error
};

Command add_run_command(CLI::App& app);
Command add_cases_command(CLI::App& app);
Command add_init_command(CLI::App& app);
Command add_keys_command(CLI::App& app);        // keys_command.cpp
Command add_render_command(CLI::App& app);
Command add_analyze_command(CLI::App& app);      // analysis_commands.cpp
Command add_convergence_command(CLI::App& app);  // analysis_commands.cpp
Command add_validate_command(CLI::App& app);     // analysis_commands.cpp
Command add_view_command(CLI::App& app);         // view_command.cpp

// The processes of an MPI run (`mpirun -np N sluice run ...`), set by main; null for one process.
void set_processes(const Communicator* comm);
const Communicator* processes();

// A case named on the command line (run_command.cpp): a built-in case name, unless a file of that
// name exists, or a case file.
Case case_from_argument(const std::string& name_or_path);

// For `sluice run --render FIELD` (render_command.cpp): the field is checked before the run (BadInput
// if unknown), and the run's animation drawn after it.
void check_render_field(const std::string& field);
void render_after_run(const std::filesystem::path& output_dir, const std::string& field, bool quiet);

// The server's options for `--host` and `--port` (view_command.cpp): a token for every request when
// the host is not this machine's loopback.
view::ServerOptions view_options(const std::string& host, int port);
// The experiment's data of a validation case, drawn over its probe series (analysis::reference_overlays).
std::vector<view::Overlay> view_overlays(const Case& c);

}  // namespace sluice::app
