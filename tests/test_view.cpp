// `sluice view`'s server (view/view_server.hpp): its endpoints from a client, what it refuses to serve,
// its token, and the frame message the page decodes.
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/run.hpp"
#include "sluice/view/view_server.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace sluice;

namespace {

// A coarse dam break run once for all the tests: 785 particles, 3 frames.
const fs::path& run_dir() {
  static const fs::path dir = [] {
    const fs::path d = fs::temp_directory_path() / fmt::format("sluice_view_test_{}", ::getpid());
    fs::remove_all(d);
    Case c = *load_builtin_case("dam_break");
    apply_overrides(c, {"domain.dx=0.4", "time.end=0.2", "output.interval=0.1"});
    RunOptions o;
    o.output_dir = d;
    o.progress = RunOptions::Progress::none;
    std::ostringstream log;
    run_case(c, o, log);
    return d;
  }();
  // Removed when the test program ends (each test runs in a program of its own under ctest).
  static const struct Remove {
    fs::path d;
    ~Remove() {
      std::error_code ec;
      fs::remove_all(d, ec);
    }
  } remove{dir};
  return dir;
}

struct Served {
  explicit Served(view::ServerOptions o = {}, fs::path dir = run_dir()) : server(dir, with_any_port(o)),
                                                                          client("127.0.0.1", server.port()) {}
  static view::ServerOptions with_any_port(view::ServerOptions o) {
    o.port = 0;
    return o;
  }
  view::ViewServer server;
  httplib::Client client;
};

// The frame message: header JSON, positions, values, kinds.
struct Decoded {
  json header;
  std::vector<float> position, value;
  std::vector<std::uint8_t> kind;
};

Decoded decode(const std::string& body) {
  Decoded d;
  std::uint32_t length = 0;
  std::memcpy(&length, body.data(), 4);
  d.header = json::parse(body.substr(4, length));
  const std::size_t n = d.header["n"], dim = d.header["dimension"];
  std::size_t at = 4 + length;
  EXPECT_EQ(body.size(), at + n * dim * 4 + n * 4 + n);
  d.position.resize(n * dim);
  std::memcpy(d.position.data(), body.data() + at, n * dim * 4);
  at += n * dim * 4;
  d.value.resize(n);
  std::memcpy(d.value.data(), body.data() + at, n * 4);
  at += n * 4;
  d.kind.assign(body.begin() + static_cast<std::ptrdiff_t>(at), body.end());
  return d;
}

}  // namespace

TEST(View, ThePageAndTheRunAreServed) {
  Served s;
  const auto page = s.client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("<canvas id=\"gl\">"), std::string::npos);
  EXPECT_EQ(s.client.Get("/view.js")->status, 200);
  const auto run = s.client.Get("/api/run");
  ASSERT_EQ(run->status, 200);
  const json r = json::parse(run->body);
  EXPECT_EQ(r["case"], "dam_break");
  ASSERT_EQ(r["frames"].size(), 3u);
  EXPECT_DOUBLE_EQ(r["frames"][2]["time"].get<double>(), 0.2);
  EXPECT_FALSE(r["live"].get<bool>());
  EXPECT_FALSE(r["running"].get<bool>());
}

TEST(View, AFrameArrivesAsTheFileHoldsIt) {
  Served s;
  const auto res = s.client.Get("/api/frame/2?field=pressure");
  ASSERT_EQ(res->status, 200);
  const Decoded d = decode(res->body);
  const Frame frame = read_npz_frame(run_dir() / "frames" / "frame_000002.npz");
  ASSERT_EQ(d.header["n"].get<std::size_t>(), frame.size());
  EXPECT_EQ(d.header["stride"], 1);
  EXPECT_DOUBLE_EQ(d.header["time"].get<double>(), frame.time);
  EXPECT_EQ(d.header["unit"], "kPa");
  for (std::size_t i = 0; i < frame.size(); i += 97) {
    EXPECT_EQ(d.position[2 * i], static_cast<float>(frame.position()[2 * i]));
    EXPECT_EQ(d.position[2 * i + 1], static_cast<float>(frame.position()[2 * i + 1]));
    EXPECT_FLOAT_EQ(d.value[i], static_cast<float>(frame.pressure()[i] * 1e-3));
    EXPECT_EQ(d.kind[i] == 0, frame.kind()[i] == 0);
  }
}

TEST(View, ALargeFrameIsThinnedToTheLimit) {
  view::ServerOptions o;
  o.max_particles = 100;
  Served s(o);
  const Decoded d = decode(s.client.Get("/api/frame/0")->body);
  const std::size_t total = d.header["total"];
  EXPECT_LE(d.header["n"].get<std::size_t>(), 100u);
  EXPECT_EQ(d.header["stride"].get<std::size_t>(), (total + 99) / 100);
}

TEST(View, NothingOutsideTheRunsOwnOutputsIsServed) {
  Served s;
  for (const char* path : {"/../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/api/frame/../../etc/passwd",
                           "/api/frame/%2e%2e%2fsummary.txt", "/etc/passwd", "//etc/passwd", "/summary.txt",
                           "/frames/frame_000000.npz", "/api/frame/-1", "/api/frame/7", "/checkpoint.bin"}) {
    const auto res = s.client.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_TRUE(res->status == 404 || res->status == 400) << path << ": " << res->status;
    EXPECT_EQ(res->body.find("root:"), std::string::npos) << path;
  }
  // A frame that is a link out of the run's directory is not followed.
  const fs::path other = fs::temp_directory_path() / fmt::format("sluice_view_link_{}", ::getpid());
  fs::remove_all(other);
  fs::create_directories(other / "frames");
  fs::copy_file(run_dir() / "diagnostics.csv", other / "diagnostics.csv");
  fs::create_symlink(run_dir() / "frames" / "frame_000001.npz", other / "frames" / "frame_000000.npz");
  Served linked({}, other);
  EXPECT_EQ(linked.client.Get("/api/frame/0")->status, 404);
  fs::remove_all(other);
}

TEST(View, ABadFrameIsReportedNotServed) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_view_bad_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir / "frames");
  std::ofstream(dir / "frames" / "frame_000000.npz") << "not a zip file";
  Served s({}, dir);
  const auto res = s.client.Get("/api/frame/0");
  EXPECT_EQ(res->status, 422);
  EXPECT_NE(json::parse(res->body)["error"].get<std::string>().find("frame 0 cannot be shown"), std::string::npos);
  EXPECT_EQ(s.client.Get("/api/frame/0?field=temperature")->status, 422);
  fs::remove_all(dir);
  Served good;
  const auto field = good.client.Get("/api/frame/0?field=temperature");
  EXPECT_EQ(field->status, 400);
  EXPECT_NE(field->body.find("temperature"), std::string::npos);
}

TEST(View, ControlsNeedALiveRunAndItsToken) {
  Served read_only;
  EXPECT_EQ(read_only.client.Post("/api/control/pause", "", "text/plain")->status, 403);

  std::atomic<bool> stop{false};
  view::Controls controls;
  controls.stop = &stop;
  view::ServerOptions o;
  o.controls = &controls;
  Served live(o);
  const std::string address = live.server.address();
  const std::string token = address.substr(address.find("token=") + 6);
  EXPECT_EQ(token.size(), 32u);
  EXPECT_EQ(live.client.Post("/api/control/pause", "", "text/plain")->status, 403);
  EXPECT_EQ(live.client.Post("/api/control/pause?token=" + std::string(32, '0'), "", "text/plain")->status, 403);
  EXPECT_FALSE(controls.pause.load());
  EXPECT_EQ(live.client.Post("/api/control/pause?token=" + token, "", "text/plain")->status, 200);
  EXPECT_TRUE(controls.pause.load());
  EXPECT_EQ(live.client.Post("/api/control/checkpoint?token=" + token, "", "text/plain")->status, 200);
  EXPECT_TRUE(controls.checkpoint.load());
  EXPECT_EQ(live.client.Post("/api/control/stop?token=" + token, "", "text/plain")->status, 200);
  EXPECT_TRUE(stop.load());
  EXPECT_FALSE(controls.pause.load());  // a stop ends a pause
  // Looking needs no token on this machine.
  EXPECT_EQ(live.client.Get("/api/run")->status, 200);
  // A request body beyond the small limit is refused.
  EXPECT_EQ(live.client.Post("/api/control/pause?token=" + token, std::string(100000, 'x'), "text/plain")->status, 413);
}

TEST(View, AnotherHostNeedsTheTokenForEverything) {
  view::ServerOptions o;
  o.token_for_everything = true;
  Served s(o);
  const std::string address = s.server.address();
  ASSERT_NE(address.find("?token="), std::string::npos);
  const std::string token = address.substr(address.find("token=") + 6);
  EXPECT_EQ(s.client.Get("/")->status, 403);
  EXPECT_EQ(s.client.Get("/api/frame/0")->status, 403);
  EXPECT_EQ(s.client.Get("/?token=" + token)->status, 200);
  httplib::Headers header{{"X-Sluice-Token", token}};
  EXPECT_EQ(s.client.Get("/api/run", header)->status, 200);
}

TEST(View, APortInUseIsRefusedWithAMessage) {
  Served first;
  view::ServerOptions o;
  o.port = first.server.port();
  try {
    view::ViewServer second(run_dir(), o);
    FAIL() << "a second server on the same port";
  } catch (const view::ViewError& e) {
    EXPECT_NE(std::string(e.what()).find(fmt::format("{}", o.port)), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("--port"), std::string::npos);
  }
}

// A validation case's reference data come with the series, thinned to at most 4000 points.
TEST(ViewServer, ServesTheReferenceDataWithTheSeries) {
  view::ServerOptions o;
  view::Overlay ref{"probes", "wall_pressure", "pressure", "Buchner (2002)", false, {}, {}};
  for (int k = 0; k < 10000; ++k) {
    ref.t.push_back(0.001 * k);
    ref.value.push_back(100.0 * k);
  }
  o.overlays.push_back(ref);
  Served s(o);
  const auto res = s.client.Get("/api/series");
  ASSERT_TRUE(res);
  const json j = json::parse(res->body);
  ASSERT_EQ(j["references"].size(), 1u);
  const json& r = j["references"][0];
  EXPECT_EQ(r["label"], "Buchner (2002)");
  EXPECT_EQ(r["series"], "wall_pressure");
  EXPECT_LE(r["t"].size(), 4000u);
  EXPECT_GE(r["t"].size(), 3000u);
  EXPECT_EQ(r["t"].size(), r["value"].size());
  EXPECT_DOUBLE_EQ(r["value"][1].get<double>(), 100.0 * 1000.0 * r["t"][1].get<double>());
}
