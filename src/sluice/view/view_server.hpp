// `sluice view`: a run shown in the browser. An HTTP server (cpp-httplib) serves the page (built into
// the program) and the run directory's data through a fixed set of endpoints: the run's description,
// one frame at a time as binary arrays, the probe and body series, the diagnostics. It never serves a
// file by a name the request gives, so nothing outside the run's own outputs can be reached. For a run
// in progress (`sluice run --view`) it also takes the page's controls (pause, resume, checkpoint,
// stop), which need the token printed with the address.
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace sluice::view {

// What a running run lets the page ask for; the run polls these between steps.
struct Controls {
  std::atomic<bool> pause{false};
  std::atomic<bool> checkpoint{false};
  std::atomic<bool>* stop = nullptr;  // the run's Ctrl-C flag
};

// Reference data drawn over one of the run's series (a validation case's experiment).
struct Overlay {
  std::string group;   // "probes" or "bodies"
  std::string series;  // the file's stem
  std::string column;  // the run's column it is drawn against
  std::string label;   // where the data come from
  bool from_first_value = false;  // departures from rest: drawn from the run's first value of the column
  std::vector<double> t, value;   // on the run's clock, in the column's units
};

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8050;  // 0: any free port (port() says which)
  // Required with every request when not empty (another host than 127.0.0.1), and for the controls
  // always; made at random when empty and needed.
  std::string token;
  bool token_for_everything = false;
  Controls* controls = nullptr;  // live mode: the run's controls (null: read-only)
  // The largest frame sent whole; a larger one is thinned to about this many particles.
  std::size_t max_particles = 250000;
  std::vector<Overlay> overlays;  // sent with the series (GET /api/series: "references")
};

// Thrown by the server for a port in use or an address it cannot listen on.
struct ViewError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class ViewServer {
 public:
  // Binds the port (ViewError if it is in use); serves from a thread of its own until stop().
  ViewServer(std::filesystem::path run_dir, ServerOptions options);
  ~ViewServer();
  ViewServer(const ViewServer&) = delete;
  ViewServer& operator=(const ViewServer&) = delete;

  // The address to open, with the token when there is one: http://127.0.0.1:8050/?token=...
  [[nodiscard]] std::string address() const;
  [[nodiscard]] int port() const;
  void stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A random token of 128 bits as 32 hex digits, from the system's random source.
[[nodiscard]] std::string random_token();

}  // namespace sluice::view
