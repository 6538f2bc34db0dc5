#include "sluice/render/color_range.hpp"

#include <algorithm>
#include <cmath>

namespace sluice::render {

namespace {

double quantile(std::vector<float>& v, double q) {
  const auto k = static_cast<std::size_t>(std::llround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// A range that contains a uniform field's value `v`.
Range around(const FieldInfo& info, double v) {
  if (info.is_signed) return {-1.0, 1.0};
  if (info.field == Field::speed) return {0.0, 1.0};
  const double half = std::max(1e-3 * std::abs(v), 0.5);
  return {v - half, v + half};
}

}  // namespace

Range data_range(const FieldInfo& info, std::vector<float> samples) {
  std::erase_if(samples, [](float v) { return !std::isfinite(v); });
  Range r{0.0, 1.0};
  if (!samples.empty()) {
    if (info.is_signed) {
      for (float& v : samples) v = std::abs(v);
      const double m = quantile(samples, 0.999);
      r = {-m, m};
    } else if (info.field == Field::speed) {
      r = {0.0, quantile(samples, 0.999)};
    } else {
      r.lo = quantile(samples, 0.001);
      r.hi = quantile(samples, 0.999);
    }
  }
  const double size = std::max({1.0, std::abs(r.lo), std::abs(r.hi)});
  if (r.hi - r.lo <= 1e-9 * size) r = around(info, r.lo);
  return r;
}

}  // namespace sluice::render
