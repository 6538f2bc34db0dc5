#include "sluice/case/motions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "sluice/case/case_error.hpp"
#include "sluice/case/value_text.hpp"

namespace sluice {

namespace fs = std::filesystem;

void load_motion_files(Case& c, const std::string& source) {
  for_each_motion_law(c, [&](MotionLawSpec& m, const std::string& key, bool /*rotation*/) {
      if (m.law != MotionLawType::file) {
        m.series = nullptr;
        return;
      }
      const std::string written = m.file;  // as the case file says it, for messages
      const fs::path given(m.file);
      const fs::path path = given.is_absolute() || c.mesh_directory.empty() ? given : fs::path(c.mesh_directory) / given;
      try {
        m.series = std::make_shared<const MotionSeries>(
            read_motion_csv(path, m.time_column, m.column, m.scale, m.time_offset));
      } catch (const MotionError& e) {
        throw CaseError(fmt::format("{}: {}.file = {}: {}", source, key, quote(written), e.what()));
      }
      std::error_code ec;
      const fs::path absolute = fs::absolute(path, ec).lexically_normal();
      if (!ec) m.file = absolute.string();
      const double last = m.series->times.back();
      if (m.past_end == PastFileEnd::error && c.end_time > last)
        throw CaseError(fmt::format("{}: {}.file = {}: its last time is t = {} s (file time + time_offset), before "
                                    "time.end = {} s; expected a file that covers the run, or {}.past_end = \"hold\" "
                                    "to keep the wall at its last position after it",
                                    source, key, quote(written), last, c.end_time, key));
  });
}

}  // namespace sluice
