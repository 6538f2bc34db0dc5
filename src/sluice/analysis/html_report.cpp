#include "sluice/analysis/html_report.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "sluice/analysis/svg_plot.hpp"

namespace sluice::analysis {

HtmlReport::HtmlReport(std::string title) : title_(std::move(title)) {}

void HtmlReport::heading(const std::string& text, int level) {
  level = std::clamp(level, 1, 4);
  body_ += fmt::format("<h{0}>{1}</h{0}>\n", level, xml_escape(text));
}

void HtmlReport::paragraph(const std::string& text) { body_ += "<p>" + xml_escape(text) + "</p>\n"; }

void HtmlReport::table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n";
  if (std::any_of(header.begin(), header.end(), [](const std::string& h) { return !h.empty(); })) {
    body_ += "<tr>";
    for (const auto& h : header) body_ += "<th>" + xml_escape(h) + "</th>";
    body_ += "</tr>\n";
  }
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const auto& cell : row) {
      const char* cls = cell.rfind("PASS", 0) == 0 ? " class=\"pass\"" : cell.rfind("FAIL", 0) == 0 ? " class=\"fail\"" : "";
      body_ += fmt::format("<td{}>{}</td>", cls, xml_escape(cell));
    }
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::figure(const std::string& svg, const std::string& caption) {
  body_ += "<figure>\n" + svg + "<figcaption>" + xml_escape(caption) + "</figcaption>\n</figure>\n";
}

std::string HtmlReport::html() const {
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{0}</title>\n<style>\n"
      "body {{ font-family: 'DejaVu Sans', Arial, sans-serif; max-width: 980px; margin: 2em auto; padding: 0 1em; "
      "color: #222; line-height: 1.45; }}\n"
      "h1 {{ font-size: 1.6em; }} h2 {{ margin-top: 1.8em; border-bottom: 1px solid #ccc; }}\n"
      "table {{ border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }}\n"
      "th, td {{ border: 1px solid #bbb; padding: 0.25em 0.6em; text-align: left; }}\n"
      "th {{ background: #f2f2f2; }}\n"
      "td.pass {{ background: #e3f4e3; }} td.fail {{ background: #f8dcdc; }}\n"
      "figure {{ margin: 1em 0; }} figcaption {{ font-size: 0.9em; color: #555; }}\n"
      "pre {{ background: #f6f6f6; padding: 0.6em; overflow-x: auto; }}\n"
      "</style>\n</head>\n<body>\n<h1>{0}</h1>\n{1}</body>\n</html>\n",
      xml_escape(title_), body_);
}

}  // namespace sluice::analysis
