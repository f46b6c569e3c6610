#include "plot_axis.h"

#include <cmath>
#include <cstdio>

namespace mb2co {
namespace lab {

std::string PlotAxis::label(int k) const {
  // Steps are 1, 2 or 5 x 10^e: a negative exponent needs -e decimals.
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, step * k);
  return text;
}

PlotAxis round_axis(double data_max, int max_ticks) {
  PlotAxis a;
  if (!(data_max > 0) || max_ticks < 1) return a;
  // Start one decade below the even split and walk up 1, 2, 5, 10, ...:
  // the first step that covers data_max in max_ticks steps is the finest.
  double decade = std::pow(10.0, std::floor(std::log10(data_max / max_ticks)));
  for (;;) {
    for (double m : {1.0, 2.0, 5.0}) {
      const double step = m * decade;
      // The small slack keeps 30.0000001 (a float sum) from needing a new tick.
      const int ticks = static_cast<int>(std::ceil(data_max / step - 1e-9));
      if (ticks <= max_ticks) {
        a.step = step;
        a.ticks = std::max(1, ticks);
        return a;
      }
    }
    decade *= 10;
  }
}

}  // namespace lab
}  // namespace mb2co
