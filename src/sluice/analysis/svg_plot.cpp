#include "sluice/analysis/svg_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "sluice/analysis/series.hpp"

namespace sluice::analysis {

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

PlotSeries curve(std::string label, std::vector<double> x, std::vector<double> y, PlotSeries::Style style) {
  PlotSeries s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = style;
  return s;
}

std::vector<double> nice_ticks(double lo, double hi, int target) {
  if (!(hi > lo)) return {lo};
  const double raw = (hi - lo) / std::max(1, target);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  double step = magnitude;
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * magnitude >= raw) {
      step = m * magnitude;
      break;
    }
  std::vector<double> ticks;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0)
    ticks.push_back(std::abs(k) < 0.5 ? 0.0 : k * step);
  return ticks;
}

namespace {

const char* const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};

// A number as a tick label: no more digits than the tick step needs.
std::string tick_label(double v, double step) {
  if (v == 0.0) return "0";
  const double a = std::abs(v);
  if (a >= 1e5 || a < 1e-3) return fmt::format("{:.3g}", v);
  const int decimals = std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9)));
  return fmt::format("{:.{}f}", v, decimals);
}

struct Axis {
  bool log = false;
  double lo = 0.0, hi = 1.0;  // in data units
  double pixel_lo = 0.0, pixel_hi = 1.0;
  [[nodiscard]] double map(double v) const {
    const double a = log ? std::log10(lo) : lo, b = log ? std::log10(hi) : hi;
    const double u = log ? std::log10(v) : v;
    return pixel_lo + (u - a) / (b - a) * (pixel_hi - pixel_lo);
  }
  // Ticks with their labels.
  [[nodiscard]] std::vector<std::pair<double, std::string>> ticks() const {
    std::vector<std::pair<double, std::string>> out;
    if (!log) {
      const auto t = nice_ticks(lo, hi);
      const double step = t.size() > 1 ? t[1] - t[0] : 1.0;
      for (double v : t) out.emplace_back(v, tick_label(v, step));
      return out;
    }
    const int first = static_cast<int>(std::floor(std::log10(lo) + 1e-9));
    const int last = static_cast<int>(std::ceil(std::log10(hi) - 1e-9));
    const bool few_decades = last - first <= 2;
    for (int e = first; e <= last; ++e)
      for (double m : {1.0, 2.0, 5.0}) {
        if (m != 1.0 && !few_decades) continue;
        const double v = m * std::pow(10.0, e);
        if (v < lo * (1 - 1e-9) || v > hi * (1 + 1e-9)) continue;
        out.emplace_back(v, fmt::format("{:g}", v));
      }
    return out;
  }
};

// Data extent of the finite (and, on a log axis, positive) values.
std::pair<double, double> extent(const Plot& plot, bool x_axis, bool log) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : plot.series) {
    const auto& v = x_axis ? s.x : s.y;
    for (std::size_t i = 0; i < v.size() && i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      if (log && !(v[i] > 0.0))
        throw AnalysisError(fmt::format("plot '{}': series '{}' has a value {} on a logarithmic axis", plot.title,
                                        s.label, v[i]));
      lo = std::min(lo, v[i]);
      hi = std::max(hi, v[i]);
    }
  }
  if (x_axis)
    for (const auto& b : plot.bands) {
      lo = std::min(lo, b.x_min);
      hi = std::max(hi, b.x_max);
    }
  if (!(lo <= hi)) throw AnalysisError(fmt::format("plot '{}': no finite points to draw", plot.title));
  if (log) {
    // Rounded out to 1, 2 or 5 times a power of ten.
    auto down = [](double v) {
      const double p = std::pow(10.0, std::floor(std::log10(v) + 1e-9));
      for (double m : {5.0, 2.0, 1.0})
        if (m * p <= v * (1 + 1e-9)) return m * p;
      return p;
    };
    auto up = [](double v) {
      const double p = std::pow(10.0, std::floor(std::log10(v) + 1e-9));
      for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= v * (1 - 1e-9)) return m * p;
      return 10.0 * p;
    };
    const double a = down(lo), b = up(hi);
    return {a, b > a ? b : up(a * 1.5)};
  }
  if (hi == lo) {
    const double pad = lo == 0.0 ? 1.0 : 0.1 * std::abs(lo);
    return {lo - pad, hi + pad};
  }
  const auto t = nice_ticks(lo, hi);
  const double step = t.size() > 1 ? t[1] - t[0] : (hi - lo);
  return {std::floor(lo / step + 1e-9) * step, std::ceil(hi / step - 1e-9) * step};
}

// The plot area inside the picture's margins, the axes that map data into it, and the id of the
// clip path that keeps the series inside it.
struct Canvas {
  explicit Canvas(const Plot& p) : plot(p) {}

  const Plot& plot;
  double left = 70, right = 20, top = 20, bottom = 55;
  double w = 0, h = 0;
  Axis ax, ay;
  std::string clip;

  [[nodiscard]] double inner_w() const { return w - left - right; }
  [[nodiscard]] double inner_h() const { return h - top - bottom; }
};

// Clip ids must be unique within an HTML page holding several plots: derived from the plot's content.
std::string clip_id(const Plot& plot) {
  std::string identity = plot.title + plot.x_label + plot.y_label;
  for (const auto& series : plot.series) identity += fmt::format("{}{}", series.label, series.x.size());
  return fmt::format("plotarea{:x}", std::hash<std::string>{}(identity));
}

Canvas make_canvas(const Plot& plot) {
  Canvas c(plot);
  c.top = plot.title.empty() ? 20 : 40;
  c.w = plot.width;
  c.h = plot.height;
  c.ax.log = plot.log_x;
  c.ay.log = plot.log_y;
  std::tie(c.ax.lo, c.ax.hi) = plot.x_range ? *plot.x_range : extent(plot, true, plot.log_x);
  std::tie(c.ay.lo, c.ay.hi) = plot.y_range ? *plot.y_range : extent(plot, false, plot.log_y);
  const Axis &ax = c.ax, &ay = c.ay;
  if (!(ax.hi > ax.lo) || !(ay.hi > ay.lo) || (ax.log && !(ax.lo > 0.0)) || (ay.log && !(ay.lo > 0.0)))
    throw AnalysisError(fmt::format("plot '{}': empty or invalid axis range", plot.title));
  c.ax.pixel_lo = c.left;
  c.ax.pixel_hi = c.w - c.right;
  c.ay.pixel_lo = c.h - c.bottom;
  c.ay.pixel_hi = c.top;
  c.clip = clip_id(plot);
  return c;
}

// The opening tag, a white background, the clip path and the title.
std::string header(const Canvas& c) {
  std::string s = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"DejaVu Sans, Arial, sans-serif\" font-size=\"13\">\n"
      "<rect width=\"{0}\" height=\"{1}\" fill=\"white\"/>\n",
      c.plot.width, c.plot.height);
  s += fmt::format("<defs><clipPath id=\"{}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath></defs>\n",
                   c.clip, c.left, c.top, c.inner_w(), c.inner_h());
  if (!c.plot.title.empty())
    s += fmt::format("<text x=\"{}\" y=\"24\" text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">{}</text>\n",
                     0.5 * (c.left + c.w - c.right), xml_escape(c.plot.title));
  return s;
}

// Shaded x-intervals, each with its label at its foot.
std::string bands(const Canvas& c) {
  std::string s;
  for (const auto& b : c.plot.bands) {
    const double x0 = std::clamp(c.ax.map(b.x_min), c.left, c.w - c.right);
    const double x1 = std::clamp(c.ax.map(b.x_max), c.left, c.w - c.right);
    s += fmt::format("<rect x=\"{:.2f}\" y=\"{}\" width=\"{:.2f}\" height=\"{}\" fill=\"#f0f0f0\"/>\n", x0, c.top,
                     x1 - x0, c.inner_h());
    if (!b.label.empty())
      s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\" fill=\"#777\" font-size=\"11\">{}</text>\n",
                       0.5 * (x0 + x1), c.h - c.bottom - 6, xml_escape(b.label));
  }
  return s;
}

// Grid lines, ticks and tick labels of both axes, the frame of the plot area and the axis labels.
std::string axes(const Canvas& c) {
  const double left = c.left, right = c.right, top = c.top, bottom = c.bottom, w = c.w, h = c.h;
  std::string s;
  for (const auto& [v, label] : c.ax.ticks()) {
    const double x = c.ax.map(v);
    s += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1}\" x2=\"{0:.2f}\" y2=\"{2}\" stroke=\"#e3e3e3\"/>\n", x, top, h - bottom);
    s += fmt::format("<line x1=\"{0:.2f}\" y1=\"{1}\" x2=\"{0:.2f}\" y2=\"{2}\" stroke=\"black\"/>\n", x, h - bottom,
                     h - bottom + 5);
    s += fmt::format("<text x=\"{:.2f}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", x, h - bottom + 19,
                     xml_escape(label));
  }
  for (const auto& [v, label] : c.ay.ticks()) {
    const double y = c.ay.map(v);
    s += fmt::format("<line x1=\"{1}\" y1=\"{0:.2f}\" x2=\"{2}\" y2=\"{0:.2f}\" stroke=\"#e3e3e3\"/>\n", y, left, w - right);
    s += fmt::format("<line x1=\"{1}\" y1=\"{0:.2f}\" x2=\"{2}\" y2=\"{0:.2f}\" stroke=\"black\"/>\n", y, left - 5, left);
    s += fmt::format("<text x=\"{}\" y=\"{:.2f}\" text-anchor=\"end\">{}</text>\n", left - 8, y + 4.5, xml_escape(label));
  }
  s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n", left, top,
                   c.inner_w(), c.inner_h());
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", 0.5 * (left + w - right), h - 12,
                   xml_escape(c.plot.x_label));
  s += fmt::format("<text transform=\"translate(16,{:.2f}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                   0.5 * (top + h - bottom), xml_escape(c.plot.y_label));
  return s;
}

// One series: its line (broken at points that cannot be drawn) and/or its markers.
std::string series_marks(const Canvas& c, const PlotSeries& series, const std::string& colour) {
  const std::size_t n = std::min(series.x.size(), series.y.size());
  auto drawable = [&](std::size_t i) {
    return std::isfinite(series.x[i]) && std::isfinite(series.y[i]) && (!c.ax.log || series.x[i] > 0.0) &&
           (!c.ay.log || series.y[i] > 0.0);
  };
  std::string s;
  if (series.style != PlotSeries::Style::markers) {
    std::string path;
    bool pen_down = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!drawable(i)) {
        pen_down = false;
        continue;
      }
      path += fmt::format("{}{:.2f},{:.2f} ", pen_down ? "L" : "M", c.ax.map(series.x[i]), c.ay.map(series.y[i]));
      pen_down = true;
    }
    s += fmt::format("<path d=\"{}\" stroke=\"{}\"{}/>\n", path, colour, series.dashed ? " stroke-dasharray=\"6,4\"" : "");
  }
  if (series.style != PlotSeries::Style::line)
    for (std::size_t i = 0; i < n; ++i)
      if (drawable(i))
        s += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3.2\" stroke=\"{}\" fill=\"white\"/>\n",
                         c.ax.map(series.x[i]), c.ay.map(series.y[i]), colour);
  return s;
}

// Each series' colour: its own, or the next of the palette.
std::vector<std::string> series_colours(const Plot& plot) {
  std::vector<std::string> colours;
  std::size_t next_colour = 0;
  for (const auto& series : plot.series)
    colours.push_back(series.colour.empty() ? palette[next_colour++ % (sizeof(palette) / sizeof(palette[0]))]
                                            : series.colour);
  return colours;
}

// The series, clipped to the plot area.
std::string all_series(const Canvas& c, const std::vector<std::string>& colours) {
  std::string s = fmt::format("<g clip-path=\"url(#{})\" fill=\"none\" stroke-width=\"1.8\">\n", c.clip);
  for (std::size_t k = 0; k < c.plot.series.size(); ++k) s += series_marks(c, c.plot.series[k], colours[k]);
  return s + "</g>\n";
}

// A box in the chosen corner listing the labelled series, each with a sample of its line or marker.
std::string legend(const Canvas& c, const std::vector<std::string>& colours) {
  const Plot& plot = c.plot;
  std::vector<std::size_t> listed;
  std::size_t longest = 0;
  for (std::size_t k = 0; k < plot.series.size(); ++k)
    if (!plot.series[k].label.empty()) {
      listed.push_back(k);
      longest = std::max(longest, plot.series[k].label.size());
    }
  if (listed.empty()) return "";
  const double box_w = 40 + 7.2 * static_cast<double>(longest), box_h = 8 + 18 * static_cast<double>(listed.size());
  const bool at_right = plot.legend == Plot::LegendAt::top_right || plot.legend == Plot::LegendAt::bottom_right;
  const bool at_bottom = plot.legend == Plot::LegendAt::bottom_left || plot.legend == Plot::LegendAt::bottom_right;
  const double x0 = at_right ? c.w - c.right - 10 - box_w : c.left + 10;
  const double y0 = at_bottom ? c.h - c.bottom - 10 - box_h : c.top + 10;
  std::string s = fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"white\" "
                              "fill-opacity=\"0.9\" stroke=\"#999\"/>\n",
                              x0, y0, box_w, box_h);
  for (std::size_t row = 0; row < listed.size(); ++row) {
    const auto& series = plot.series[listed[row]];
    const std::string& colour = colours[listed[row]];
    const double y = y0 + 16 + 18 * static_cast<double>(row);
    if (series.style != PlotSeries::Style::markers)
      s += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" stroke-width=\"1.8\"{}/>\n",
                       x0 + 6, y - 4, x0 + 30, y - 4, colour, series.dashed ? " stroke-dasharray=\"6,4\"" : "");
    if (series.style != PlotSeries::Style::line)
      s += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.2\" stroke=\"{}\" fill=\"white\" stroke-width=\"1.8\"/>\n",
                       x0 + 18, y - 4, colour);
    s += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>\n", x0 + 36, y, xml_escape(series.label));
  }
  return s;
}

}  // namespace

std::string svg_plot(const Plot& plot) {
  if (plot.series.empty()) throw AnalysisError(fmt::format("plot '{}': no series to draw", plot.title));
  const Canvas c = make_canvas(plot);
  const std::vector<std::string> colours = series_colours(plot);
  return header(c) + bands(c) + axes(c) + all_series(c, colours) + legend(c, colours) + "</svg>\n";
}

}  // namespace sluice::analysis
