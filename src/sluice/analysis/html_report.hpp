// A self-contained HTML page: headings, paragraphs, tables and SVG figures embedded inline, with a
// small stylesheet. Opens in any browser with no other file.
#pragma once

#include <string>
#include <vector>

namespace sluice::analysis {

class HtmlReport {
 public:
  explicit HtmlReport(std::string title);

  void heading(const std::string& text, int level = 2);
  void paragraph(const std::string& text);  // plain text, escaped
  // A table of plain-text cells (no header row if every header is empty); a cell starting with "PASS"
  // or "FAIL" is coloured.
  void table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  void figure(const std::string& svg, const std::string& caption);

  [[nodiscard]] std::string html() const;

 private:
  std::string title_;
  std::string body_;
};

}  // namespace sluice::analysis
