// Axis scales for the lab's SVG plots: tick values a reader can add up in
// their head (1, 2 or 5 times a power of ten), so a histogram's time axis
// reads 0, 10, 20 ... ms instead of 8, 16, ..., 49, 57.
#pragma once

#include <string>

namespace mb2co {
namespace lab {

/// An axis from 0 to `max` in `ticks` equal steps of `step` (max == step * ticks
/// exactly in decimal: step is 1, 2 or 5 times a power of ten).
struct PlotAxis {
  double step = 1;
  int ticks = 1;
  double max() const { return step * ticks; }
  /// Tick k (0..ticks) as text, with as many decimals as the step needs.
  std::string label(int k) const;
};

/// The smallest axis with at most `max_ticks` steps whose end is at or above
/// `data_max`. data_max <= 0 gives 0..1 in one step. max_ticks >= 1.
PlotAxis round_axis(double data_max, int max_ticks);

}  // namespace lab
}  // namespace mb2co
