// Numeric CSV tables: the reference data in data/validation/ (with its '#' provenance lines) and the
// probe series a run writes (time,value,...). Read with line numbers in every error; written back
// with the provenance kept.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "sluice/analysis/series.hpp"

namespace sluice::analysis {

struct Table {
  std::vector<std::string> comments;  // the leading '#' lines, without the '#'
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;

  // Index of a column; throws AnalysisError naming the table and its columns if there is none.
  [[nodiscard]] std::size_t column(std::string_view name) const;
  [[nodiscard]] std::vector<double> values(std::string_view name) const;
  // (x column, y column) as a series sorted by x.
  [[nodiscard]] Series series(std::string_view x, std::string_view y) const;

  std::string source;  // file name or description, for error messages
};

// `source` names the text in error messages. Leading lines starting with '#' are comments; the first
// other line is the header; every later non-empty line must hold one number per column.
Table parse_csv_table(std::string_view text, const std::string& source);
Table read_csv_table(const std::filesystem::path& path);

// The table as CSV: comments (each line prefixed with '#'), header, rows (full precision).
std::string csv_text(const Table& t);

}  // namespace sluice::analysis
