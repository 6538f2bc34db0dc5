#include "sluice/view/view_server.hpp"

#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <thread>
#include <vector>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/io/run_outputs.hpp"
#include "sluice/render/colormap.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/render_error.hpp"
#include "view_page.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace sluice::view {

namespace {

// The frames of a run directory by index, from their file names (frame_NNNNNN.npz).
std::map<std::int64_t, fs::path> list_frames(const fs::path& dir) {
  std::map<std::int64_t, fs::path> frames;
  std::error_code ec;
  static const std::regex name(R"(frame_(\d{6,})\.npz)");
  for (const auto& e : fs::directory_iterator(dir / output_files::frames_dir, ec)) {
    std::smatch m;
    const std::string file = e.path().filename().string();
    if (std::regex_match(file, m, name)) frames[std::stoll(m[1].str())] = e.path();
  }
  return frames;
}

// A numeric CSV (a header line, then numbers; "nan" where a value is not defined) that the run may be
// appending to: its whole lines.
struct Csv {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

std::optional<Csv> read_growing_csv(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return std::nullopt;
  const std::string text = read_file(path);
  Csv csv;
  std::size_t at = 0;
  bool header = true;
  while (true) {
    const std::size_t end = text.find('\n', at);
    if (end == std::string::npos) break;  // a line still being written
    const std::string line = text.substr(at, end - at);
    at = end + 1;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::size_t from = 0;
    while (true) {
      const std::size_t comma = line.find(',', from);
      cells.push_back(line.substr(from, comma == std::string::npos ? std::string::npos : comma - from));
      if (comma == std::string::npos) break;
      from = comma + 1;
    }
    if (header) {
      csv.columns = cells;
      header = false;
      continue;
    }
    if (cells.size() != csv.columns.size())
      throw FormatError(fmt::format("{}: a row of {} values under {} columns", path.filename().string(), cells.size(),
                                    csv.columns.size()));
    std::vector<double> row;
    for (const std::string& cell : cells) {
      char* rest = nullptr;
      const double v = std::strtod(cell.c_str(), &rest);
      if (rest == cell.c_str() || *rest != '\0')
        throw FormatError(fmt::format("{}: '{}' is not a number", path.filename().string(), cell));
      row.push_back(v);
    }
    csv.rows.push_back(std::move(row));
  }
  if (header) return std::nullopt;
  return csv;
}

// A table as JSON: its columns and at most `most` rows, evenly thinned (the last row kept); a value
// that is not finite is null.
json table_json(const Csv& t, std::size_t most = 2000) {
  json rows = json::array();
  const std::size_t n = t.rows.size();
  const std::size_t stride = n > most ? (n + most - 1) / most : 1;
  auto row_json = [](const std::vector<double>& r) {
    json out = json::array();
    for (const double v : r) out.push_back(std::isfinite(v) ? json(v) : json(nullptr));
    return out;
  };
  for (std::size_t k = 0; k < n; k += stride) rows.push_back(row_json(t.rows[k]));
  if (n > 0 && (n - 1) % stride != 0) rows.push_back(row_json(t.rows[n - 1]));
  return {{"columns", t.columns}, {"rows", rows}};
}

json series_json(const fs::path& dir) {
  json out = json::object();
  std::error_code ec;
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".csv") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    try {
      if (auto t = read_growing_csv(f)) out[f.stem().string()] = table_json(*t);
    } catch (const std::exception& e) {
      out[f.stem().string()] = {{"error", e.what()}};
    }
  }
  return out;
}

// An overlay's data, thinned to at most `most` points (the page's plots are a few hundred pixels wide).
json overlay_json(const Overlay& o, std::size_t most = 4000) {
  const std::size_t n = std::min(o.t.size(), o.value.size());
  const std::size_t stride = n > most ? (n + most - 1) / most : 1;
  json t = json::array(), v = json::array();
  for (std::size_t k = 0; k < n; k += stride)
    if (std::isfinite(o.t[k]) && std::isfinite(o.value[k])) t.push_back(o.t[k]), v.push_back(o.value[k]);
  return {{"group", o.group}, {"series", o.series}, {"column", o.column}, {"label", o.label},
          {"from_first_value", o.from_first_value}, {"t", t}, {"value", v}};
}

// The case's name: the ParaView index's, or the summary's.
std::string case_name(const fs::path& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.path().extension() == ".pvd") return e.path().stem().string();
  std::ifstream summary(dir / output_files::summary);
  std::string line;
  if (std::getline(summary, line)) {
    const auto a = line.find('\''), b = line.rfind('\'');
    if (a != std::string::npos && b > a) return line.substr(a + 1, b - a - 1);
  }
  return dir.filename().string();
}

void append_bytes(std::string& out, const void* data, std::size_t bytes) {
  out.append(static_cast<const char*>(data), bytes);
}

}  // namespace

std::string random_token() {
  std::random_device source;
  std::string token;
  for (int k = 0; k < 4; ++k) token += fmt::format("{:08x}", static_cast<std::uint32_t>(source()));
  return token;
}

namespace {

// The binary frame the page draws (GET /api/frame/K):
// [uint32 header bytes][header JSON, padded with spaces to 4 bytes][positions: n x dimension float32]
// [values: n float32, in the field's shown unit][kind: n uint8]. A frame of more than max_particles
// is thinned: every k-th particle of it (k the smallest that leaves at most max_particles), walls
// and water alike; the header says k ("stride") and the whole count.
std::string frame_message(const fs::path& npz, std::int64_t index, const std::string& field_name,
                          std::size_t max_particles) {
  const Frame frame = read_npz_frame(npz);
  const render::Field field = render::parse_field(field_name);
  const render::FieldInfo info = render::field_info(field, frame.dimension);
  const render::FrameData data = render::extract(frame, field);
  const std::size_t total = data.size();
  const std::size_t stride = total > max_particles ? (total + max_particles - 1) / max_particles : 1;
  const std::size_t n = (total + stride - 1) / stride;
  float lo = INFINITY, hi = -INFINITY;
  for (std::size_t i = 0; i < total; ++i)
    if (data.kind[i] == 0 && std::isfinite(data.value[i])) {
      lo = std::min(lo, data.value[i]);
      hi = std::max(hi, data.value[i]);
    }
  json header = {{"index", index},       {"time", frame.time},   {"step", frame.step},
                 {"dx", frame.dx},       {"dimension", frame.dimension}, {"n", n},
                 {"total", total},       {"stride", stride},     {"field", std::string(info.name)},
                 {"title", std::string(frame.dimension == 3 ? info.title_3d : info.title)},
                 {"unit", std::string(info.unit)}, {"signed", info.is_signed},
                 {"colormap", info.map == render::Colormap::viridis ? "viridis" : "coolwarm"}};
  if (lo <= hi) header["min"] = lo, header["max"] = hi;
  std::string text = header.dump();
  while (text.size() % 4 != 0) text += ' ';
  std::string out;
  const int dim = frame.dimension;
  out.reserve(4 + text.size() + n * (4 * static_cast<std::size_t>(dim) + 5));
  const auto length = static_cast<std::uint32_t>(text.size());
  append_bytes(out, &length, 4);
  out += text;
  std::vector<float> xyz(n * static_cast<std::size_t>(dim)), value(n);
  std::vector<std::uint8_t> kind(n);
  for (std::size_t k = 0, i = 0; i < total; i += stride, ++k) {
    xyz[k * dim] = data.x[i];
    xyz[k * dim + 1] = data.y[i];
    if (dim == 3) xyz[k * dim + 2] = data.z[i];
    value[k] = data.value[i];
    kind[k] = data.kind[i];
  }
  append_bytes(out, xyz.data(), xyz.size() * sizeof(float));
  append_bytes(out, value.data(), value.size() * sizeof(float));
  append_bytes(out, kind.data(), kind.size());
  return out;
}

}  // namespace

struct ViewServer::Impl {
  fs::path dir;
  fs::path real_dir;
  ServerOptions options;
  httplib::Server server;
  std::thread thread;
  int port = 0;

  Impl(fs::path run_dir, ServerOptions o) : dir(std::move(run_dir)), options(std::move(o)) {
    std::error_code ec;
    real_dir = fs::weakly_canonical(dir, ec);
    if ((options.token_for_everything || options.controls != nullptr) && options.token.empty())
      options.token = random_token();
    // SO_REUSEADDR alone (a restarted server gets its port back at once), not the library's default
    // SO_REUSEPORT, which would let a second server share the port silently instead of being told
    // that it is in use.
    server.set_socket_options([](socket_t sock) {
      int yes = 1;
      ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    server.set_payload_max_length(4096);
    server.new_task_queue = [] { return new httplib::ThreadPool(4); };
    server.set_read_timeout(5, 0);
    server.set_write_timeout(10, 0);
    routes();
    port = options.port == 0 ? server.bind_to_any_port(options.host)
                             : (server.bind_to_port(options.host, options.port) ? options.port : -1);
    if (port < 0)
      throw ViewError(fmt::format("cannot listen on {}:{}: the port is in use (or the address is not this machine's); "
                                  "choose another with --port",
                                  options.host, options.port));
    thread = std::thread([this] { server.listen_after_bind(); });
    // Running before the constructor returns: a stop() before the thread listens would be missed.
    for (int k = 0; k < 5000 && !server.is_running(); ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }

  ~Impl() { stop(); }

  void stop() {
    server.stop();
    if (thread.joinable()) thread.join();
  }

  [[nodiscard]] bool token_ok(const httplib::Request& req) const {
    if (options.token.empty()) return true;
    const std::string given =
        req.has_param("token") ? req.get_param_value("token") : req.get_header_value("X-Sluice-Token");
    return given.size() == options.token.size() &&
           std::equal(given.begin(), given.end(), options.token.begin());
  }

  static void error(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(json{{"error", message}}.dump(), "application/json");
  }

  // A frame file that really is in the run's frames directory (not a link out of it).
  [[nodiscard]] std::optional<fs::path> frame_file(std::int64_t index) const {
    const auto frames = list_frames(dir);
    const auto it = frames.find(index);
    if (it == frames.end()) return std::nullopt;
    std::error_code ec;
    const fs::path real = fs::weakly_canonical(it->second, ec);
    if (ec || real.parent_path() != real_dir / output_files::frames_dir) return std::nullopt;
    return it->second;
  }

  json run_json() const {
    const auto frames = list_frames(dir);
    std::optional<Csv> diagnostics;
    try {
      diagnostics = read_growing_csv(dir / output_files::diagnostics);
    } catch (const std::exception&) {
    }
    json list = json::array();
    for (const auto& [index, path] : frames) {
      json entry = {{"index", index}};
      if (diagnostics && static_cast<std::size_t>(index) < diagnostics->rows.size())
        entry["time"] = diagnostics->rows[static_cast<std::size_t>(index)][0];
      list.push_back(entry);
    }
    std::error_code ec;
    return {{"case", case_name(dir)},
            {"directory", dir.string()},
            {"frames", list},
            {"running", fs::exists(dir / ".sluice.lock", ec) && !fs::exists(dir / output_files::summary, ec)},
            {"live", options.controls != nullptr},
            {"paused", options.controls != nullptr && options.controls->pause.load()}};
  }

  void routes() {
    server.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      const bool control = req.path.rfind("/api/control/", 0) == 0;
      if ((options.token_for_everything || control) && !token_ok(req)) {
        error(res, 403, control && options.controls == nullptr
                            ? "this run is not live: the page can only look"
                            : "this page needs the token printed with its address (?token=...)");
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    server.Get("/", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(page::index_html, "text/html; charset=utf-8");
    });
    server.Get("/view.js", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(page::view_js, "text/javascript; charset=utf-8");
    });
    server.Get("/view.css", [](const httplib::Request&, httplib::Response& res) {
      res.set_content(page::view_css, "text/css; charset=utf-8");
    });
    server.Get("/api/run", [this](const httplib::Request&, httplib::Response& res) {
      res.set_content(run_json().dump(), "application/json");
    });
    server.Get("/api/colormaps", [](const httplib::Request&, httplib::Response& res) {
      json maps = json::object();
      for (const auto& [name, map] : {std::pair{"viridis", render::Colormap::viridis},
                                      std::pair{"coolwarm", render::Colormap::coolwarm}}) {
        json table = json::array();
        for (int k = 0; k < 256; ++k) {
          const render::Rgb c = render::colormap_at(map, k / 255.0);
          table.push_back({c.r, c.g, c.b});
        }
        maps[name] = table;
      }
      res.set_content(maps.dump(), "application/json");
    });
    server.Get(R"(/api/frame/(\d{1,12}))", [this](const httplib::Request& req, httplib::Response& res) {
      const std::int64_t index = std::stoll(req.matches[1].str());
      const auto file = frame_file(index);
      if (!file) return error(res, 404, fmt::format("no frame {} in this run", index));
      const std::string field = req.has_param("field") ? req.get_param_value("field") : "speed";
      try {
        res.set_content(frame_message(*file, index, field, options.max_particles), "application/octet-stream");
      } catch (const render::RenderError& e) {
        error(res, 400, e.what());
      } catch (const std::exception& e) {
        error(res, 422, fmt::format("frame {} cannot be shown: {}", index, e.what()));
      }
    });
    // Made once: the reference data do not change.
    json references = json::array();
    for (const Overlay& o : options.overlays) references.push_back(overlay_json(o));
    server.Get("/api/series", [this, references](const httplib::Request&, httplib::Response& res) {
      res.set_content(json{{"probes", series_json(dir / output_files::probes_dir)},
                           {"bodies", series_json(dir / output_files::bodies_dir)},
                           {"references", references}}
                          .dump(),
                      "application/json");
    });
    server.Get("/api/diagnostics", [this](const httplib::Request&, httplib::Response& res) {
      try {
        if (auto t = read_growing_csv(dir / output_files::diagnostics))
          return res.set_content(table_json(*t).dump(), "application/json");
        res.set_content(json{{"columns", json::array()}, {"rows", json::array()}}.dump(), "application/json");
      } catch (const std::exception& e) {
        error(res, 422, e.what());
      }
    });
    server.Post(R"(/api/control/(pause|resume|checkpoint|stop))",
                [this](const httplib::Request& req, httplib::Response& res) {
                  Controls* c = options.controls;
                  if (c == nullptr) return error(res, 403, "this run is not live: the page can only look");
                  const std::string action = req.matches[1].str();
                  if (action == "pause") c->pause = true;
                  if (action == "resume") c->pause = false;
                  if (action == "checkpoint") c->checkpoint = true;
                  if (action == "stop" && c->stop != nullptr) {
                    c->pause = false;
                    *c->stop = true;
                  }
                  res.set_content(json{{"paused", c->pause.load()}, {"done", action}}.dump(), "application/json");
                });
  }
};

ViewServer::ViewServer(fs::path run_dir, ServerOptions options)
    : impl_(std::make_unique<Impl>(std::move(run_dir), std::move(options))) {}
ViewServer::~ViewServer() = default;

std::string ViewServer::address() const {
  const std::string host = impl_->options.host == "0.0.0.0" ? "127.0.0.1" : impl_->options.host;
  std::string a = fmt::format("http://{}:{}/", host, impl_->port);
  if (!impl_->options.token.empty()) a += "?token=" + impl_->options.token;
  return a;
}

int ViewServer::port() const { return impl_->port; }

void ViewServer::stop() { impl_->stop(); }

}  // namespace sluice::view
