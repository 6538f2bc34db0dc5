#include "sluice/render/ticks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace sluice::render {

std::vector<double> nice_ticks(Range range, int max_ticks) {
  max_ticks = std::max(max_ticks, 2);
  const double span = range.hi - range.lo;
  if (!(span > 0.0) || !std::isfinite(span)) return {range.lo};
  const int e0 = static_cast<int>(std::floor(std::log10(span / max_ticks))) - 1;
  for (int e = e0; e < e0 + 6; ++e)
    for (const double m : {1.0, 2.0, 2.5, 5.0}) {
      const double step = m * std::pow(10.0, e);
      const double first = std::ceil(range.lo / step - 1e-9), last = std::floor(range.hi / step + 1e-9);
      const double count = last - first + 1;
      if (count > max_ticks) continue;
      std::vector<double> ticks;
      for (double k = first; k <= last; k += 1.0) {
        const double v = k * step;
        ticks.push_back(v == 0.0 ? 0.0 : v);  // no -0
      }
      return ticks;
    }
  return {range.lo, range.hi};
}

std::string tick_label(double value, double step) {
  int decimals = 0;
  step = std::abs(step);
  while (decimals < 6) {
    const double scaled = step * std::pow(10.0, decimals);
    if (scaled > 0 && std::abs(scaled - std::round(scaled)) < 1e-6 * std::max(1.0, scaled)) break;
    ++decimals;
  }
  std::string s = fmt::format("{:.{}f}", value, decimals);
  if (s.front() == '-') {
    if (s.find_first_not_of("-0.") == std::string::npos) return s.substr(1);  // "-0.0"
    s = "\u2212" + s.substr(1);                                                // a real minus sign
  }
  return s;
}

}  // namespace sluice::render
