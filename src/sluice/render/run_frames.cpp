#include "sluice/render/run_frames.hpp"

#include <fmt/format.h>

#include <map>
#include <regex>

#include "sluice/io/npz.hpp"
#include "sluice/render/render_error.hpp"

namespace fs = std::filesystem;

namespace sluice::render {

std::vector<std::pair<std::int64_t, fs::path>> list_frames(const fs::path& run_dir) {
  std::error_code ec;
  if (!fs::is_directory(run_dir, ec))
    throw RenderError(fmt::format("{}: no such directory (give a run's output directory, e.g. out/dam_break)",
                                  run_dir.string()));
  const fs::path dir = run_dir / "frames";
  std::map<std::int64_t, fs::path> frames;
  bool vtu = false;
  static const std::regex pattern(R"(frame_(\d{1,18})\.npz)");
  if (fs::is_directory(dir, ec))
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      std::smatch m;
      if (std::regex_match(name, m, pattern)) frames[std::stoll(m[1].str())] = entry.path();
      else if (entry.path().extension() == ".vtu") vtu = true;
    }
  if (frames.empty())
    throw RenderError(vtu ? fmt::format("{}: no .npz frames, only .vtu (render reads the .npz frames: run the case "
                                        "with output.formats including \"npz\")",
                                        dir.string())
                          : fmt::format("{}: no frames (frames/frame_NNNNNN.npz); is it a run's output directory?",
                                        run_dir.string()));
  std::vector<std::pair<std::int64_t, fs::path>> out(frames.begin(), frames.end());
  for (std::size_t k = 1; k < out.size(); ++k)
    if (out[k].first != out[k - 1].first + 1)
      throw FormatError(fmt::format("{}: frame {} is missing (frames {} to {} are there, with gaps)", dir.string(),
                                    out[k - 1].first + 1, out.front().first, out.back().first));
  return out;
}

FrameData read_frame(const fs::path& path, Field field) { return extract(read_npz_frame(path), field); }

}  // namespace sluice::render
