// The colour range: the values the colour map spans, the same in every frame of a run.
#pragma once

#include <vector>

#include "sluice/render/fields.hpp"

namespace sluice::render {

struct Range {
  double lo = 0.0, hi = 1.0;
};

// The default colour range from sampled fluid values (shown units): from the 0.1 % to the 99.9 %
// quantile, so that one outlier does not wash out the picture (from 0 for speed; symmetric about 0
// for signed fields). Values outside the range are drawn in the end colours, and the colour bar
// then has a pointed end.
Range data_range(const FieldInfo& info, std::vector<float> samples);

}  // namespace sluice::render
