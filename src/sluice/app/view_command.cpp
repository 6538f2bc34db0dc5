// `sluice view RUN_DIR`: the run in the browser (view/view_server.hpp), until Ctrl-C.
#include <fmt/format.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>
#include <utility>

#include "sluice/analysis/validation.hpp"
#include "sluice/app/commands.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/run_outputs.hpp"
#include "sluice/view/view_server.hpp"

namespace fs = std::filesystem;

namespace sluice::app {

namespace {

std::atomic<bool> view_stop{false};
extern "C" void on_view_signal(int) { view_stop.store(true); }

struct ViewArgs {
  std::string dir;
  int port = 8050;
  std::string host = "127.0.0.1";
};

int view(const ViewArgs& a) {
  std::error_code ec;
  const fs::path dir = a.dir;
  if (!fs::is_directory(dir, ec))
    throw BadInput(fmt::format("{}: no such run directory; expected the output directory of a run (sluice run -o DIR)",
                               a.dir));
  if (!fs::is_directory(dir / output_files::frames_dir, ec) && !fs::is_regular_file(dir / output_files::diagnostics, ec))
    throw BadInput(fmt::format("{}: not a sluice run: it has neither {}/ nor {} (a run writes them into its output "
                               "directory, sluice run -o DIR)",
                               a.dir, output_files::frames_dir, output_files::diagnostics));
  view::ServerOptions o = view_options(a.host, a.port);
  // The case, for its reference data, from the checkpoint (a run that has written none yet, or a
  // damaged one, is shown without them).
  try {
    if (fs::is_regular_file(dir / output_files::checkpoint, ec))
      o.overlays = view_overlays(read_checkpoint(dir / output_files::checkpoint).config);
  } catch (const std::exception&) {
  }
  view::ViewServer server(dir, o);
  std::signal(SIGINT, on_view_signal);
  std::signal(SIGTERM, on_view_signal);
  std::signal(SIGHUP, on_view_signal);
  std::cerr << fmt::format("sluice: showing {} at {}\n", a.dir, server.address());
  if (o.token_for_everything)
    std::cerr << fmt::format("sluice: listening on {} (not this machine alone): the page needs the token in its address\n",
                             a.host);
  std::cerr << "sluice: Ctrl-C stops the server\n" << std::flush;
  while (!view_stop.load()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  server.stop();
  return 0;
}

}  // namespace

view::ServerOptions view_options(const std::string& host, int port) {
  view::ServerOptions o;
  o.host = host;
  o.port = port;
  o.token_for_everything = host != "127.0.0.1" && host != "localhost" && host != "::1";
  return o;
}

std::vector<view::Overlay> view_overlays(const Case& c) {
  std::vector<view::Overlay> out;
  for (analysis::ReferenceOverlay& r : analysis::reference_overlays(c))
    out.push_back({r.group, r.series, r.column, r.label, r.from_first_value, std::move(r.data.t), std::move(r.data.y)});
  return out;
}

Command add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  auto* cmd = app.add_subcommand("view", "Show a run in the browser, finished or running (WebGL; the address is printed).");
  cmd->add_option("run_dir", args->dir, "The run's output directory")->required();
  cmd->add_option("--port", args->port, "The port to listen on (default 8050; 0: any free port)")->check(CLI::Range(0, 65535));
  cmd->add_option("--host", args->host,
                  "The address to listen on (default 127.0.0.1, this machine alone; another, such as 0.0.0.0, "
                  "requires the printed token for every request)");
  return {cmd, [args] { return view(*args); }};
}

}  // namespace sluice::app
