// Line plots as standalone SVG text: axes with round-number ticks (linear or logarithmic), labelled
// series drawn as lines and/or markers, a legend, and shaded x-intervals (a comparison window).
// Small and dependency-free, so that reports can embed their plots directly in HTML.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace sluice::analysis {

struct PlotSeries {
  enum class Style { line, markers, line_and_markers };
  std::string label;             // shown in the legend (empty: not listed)
  std::vector<double> x, y;      // non-finite points break the line
  Style style = Style::line;
  std::string colour;            // CSS colour; empty: the next colour of the palette
  bool dashed = false;
};

// A series with its label and points (colour from the palette).
PlotSeries curve(std::string label, std::vector<double> x, std::vector<double> y,
                 PlotSeries::Style style = PlotSeries::Style::line);

struct PlotBand {
  double x_min = 0.0, x_max = 0.0;
  std::string label;             // written at the foot of the band
};

struct Plot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  std::vector<PlotBand> bands;
  bool log_x = false, log_y = false;
  std::optional<std::pair<double, double>> x_range, y_range;  // default: the data's extent, rounded out
  enum class LegendAt { top_left, top_right, bottom_left, bottom_right } legend = LegendAt::top_left;
  int width = 900, height = 460;
};

// Throws AnalysisError for a plot with nothing to draw or non-positive values on a log axis.
std::string svg_plot(const Plot& plot);

// Round-number ticks covering [lo, hi] (about `target` of them): steps of 1, 2 or 5 times a power of 10.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

// Escapes &, <, >, " and ' for XML and HTML text.
std::string xml_escape(const std::string& text);

}  // namespace sluice::analysis
