#include "sluice/analysis/table.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "sluice/case/value_text.hpp"
#include "sluice/io/atomic_file.hpp"

namespace sluice::analysis {

namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

// The columns' names as messages show them (read from a file: control characters escaped).
std::string column_list(const std::vector<std::string>& columns, std::string_view separator) {
  std::string out;
  for (const auto& c : columns) out += (out.empty() ? "" : std::string(separator)) + printable(c);
  return out;
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    out.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

}  // namespace

std::size_t Table::column(std::string_view name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return i;
  throw AnalysisError(fmt::format("{}: no column '{}'; the columns are {}", source, name, column_list(columns, ", ")));
}

std::vector<double> Table::values(std::string_view name) const {
  const std::size_t k = column(name);
  std::vector<double> out;
  out.reserve(rows.size());
  for (const auto& r : rows) out.push_back(r[k]);
  return out;
}

Series Table::series(std::string_view x, std::string_view y) const { return sorted({values(x), values(y)}); }

Table parse_csv_table(std::string_view text, const std::string& source) {
  Table t;
  t.source = source;
  std::size_t line_number = 0;
  bool header = false;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const auto end = text.find('\n', pos);
    const std::string_view raw = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
    pos = end == std::string_view::npos ? text.size() + 1 : end + 1;
    ++line_number;
    const std::string_view line = trim(raw);
    if (!header && !line.empty() && line.front() == '#') {
      t.comments.emplace_back(trim(line.substr(1)));
      continue;
    }
    if (line.empty()) continue;
    const auto fields = split(line);
    if (!header) {
      for (auto f : fields) {
        if (f.empty()) throw AnalysisError(fmt::format("{}:{}: empty column name in the header", source, line_number));
        t.columns.emplace_back(f);
      }
      header = true;
      continue;
    }
    if (fields.size() != t.columns.size())
      throw AnalysisError(fmt::format("{}:{}: {} value{} in a row; expected {} ({})", source, line_number, fields.size(),
                                      fields.size() == 1 ? "" : "s", t.columns.size(), column_list(t.columns, ",")));
    std::vector<double> row;
    for (std::size_t k = 0; k < fields.size(); ++k) {
      double v = 0.0;
      const auto f = fields[k];
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec != std::errc() || ptr != f.data() + f.size() || !std::isfinite(v))
        throw AnalysisError(fmt::format("{}:{}: column '{}': '{}' is not a finite number", source, line_number,
                                        printable(t.columns[k]), printable(f)));
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
  }
  if (!header) throw AnalysisError(fmt::format("{}: no header line (expected column names such as time,value)", source));
  return t;
}

Table read_csv_table(const std::filesystem::path& path) {
  try {
    return parse_csv_table(read_file(path), path.string());
  } catch (const IoError& e) {
    throw AnalysisError(e.what());
  }
}

std::string csv_text(const Table& t) {
  std::string s;
  for (const auto& c : t.comments) s += "# " + c + "\n";
  s += fmt::format("{}\n", fmt::join(t.columns, ","));
  for (const auto& r : t.rows) s += fmt::format("{}\n", fmt::join(r, ","));
  return s;
}

}  // namespace sluice::analysis
