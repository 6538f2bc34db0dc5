// The ticks of the colour bar and their labels.
#pragma once

#include <string>
#include <vector>

#include "sluice/render/color_range.hpp"

namespace sluice::render {

// "Nice" tick values (steps of 1, 2, 2.5 or 5 times a power of ten) inside [lo, hi], at most
// max_ticks of them (at least two when the range allows), and their labels.
std::vector<double> nice_ticks(Range range, int max_ticks);
std::string tick_label(double value, double step);

}  // namespace sluice::render
