// The lab's histogram plot: one panel per measured case (samples per bin
// on a count axis, the value axis on round ticks) with the case's analytical
// bounds drawn as red lines. latency, sync-roundtrip, sync-latency,
// sync-processing and alternative all draw with it.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

namespace mb2co {
namespace lab {

/// What the samples count in and how they are shown: `per_unit` sample
/// ticks make one shown unit (ns per ms: 1e6; ns per us: 1e3; ATmega328P
/// cycles per us: 16).
struct HistogramUnit {
  const char* name;  ///< "ms", "us"
  double per_unit;
};

constexpr HistogramUnit kMs = {"ms", 1e6};  ///< samples in ns shown in ms
constexpr HistogramUnit kUs = {"us", 1e3};  ///< samples in ns shown in us

struct HistogramPanel {
  std::string name;                                ///< "modbus", "round trip"
  const std::vector<uint64_t>* samples = nullptr;  ///< in ticks; not owned
  uint64_t min = 0, max = 0;                       ///< of the samples, in ticks
  bool bounded = false;                            ///< the bound lines are drawn
  bool has_best = true;                            ///< false: only an upper bound
  uint64_t best = 0, worst = 0;                    ///< the bound, in ticks
  const char* worst_label = "worst";
  const char* fill = "#3070c0";
};

/// The SVG: `heading` then "measured histogram (<counted> per <bin> <unit>
/// bin), analytical bounds (red)"; panels stacked, one value axis for all
/// (0 to above every sample and bound, 100 bins).
std::string histogram_svg(const std::string& heading, const char* counted, const HistogramUnit& unit,
                          const std::vector<HistogramPanel>& panels);

}  // namespace lab
}  // namespace mb2co
