#include "sluice/case/motions.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string_view>

#include "sluice/case/case_error.hpp"
#include "sluice/case/reference_files.hpp"
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
      // A relative name may be a record built into the binary (data/validation/<file>): first for a
      // built-in case, after the case file's directory for a case file.
      std::error_code ec;
      std::optional<std::string_view> built_in;
      if (given.is_relative() && (c.mesh_directory.empty() || !fs::exists(path, ec)))
        built_in = reference_file_text(given.lexically_normal().generic_string());
      try {
        m.series = std::make_shared<const MotionSeries>(
            built_in ? parse_motion_csv(std::string(*built_in), written, m.time_column, m.column, m.scale, m.time_offset)
                     : read_motion_csv(path, m.time_column, m.column, m.scale, m.time_offset));
      } catch (const MotionError& e) {
        throw CaseError(fmt::format("{}: {}.file = {}: {}", source, key, quote(written), e.what()));
      }
      if (!built_in) {
        const fs::path absolute = fs::absolute(path, ec).lexically_normal();
        if (!ec) m.file = absolute.string();
      }
      const double last = m.series->times.back();
      if (m.past_end == PastFileEnd::error && c.end_time > last)
        throw CaseError(fmt::format("{}: {}.file = {}: its last time is t = {} s (file time + time_offset), before "
                                    "time.end = {} s; expected a file that covers the run, or {}.past_end = \"hold\" "
                                    "to keep the wall at its last position after it",
                                    source, key, quote(written), last, c.end_time, key));
  });
}

}  // namespace sluice
