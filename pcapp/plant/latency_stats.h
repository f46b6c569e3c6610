// Press-to-LED delays of the latency lab: min / mean / p99 / max and a text
// histogram, printed when the measurement ends.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

namespace mb2co {
namespace pcapp {

class LatencyStats {
 public:
  void add(uint32_t delay_us) { samples_.push_back(delay_us); }
  size_t count() const { return samples_.size(); }
  /// Valid when count() > 0.
  uint32_t min_us() const;
  uint32_t max_us() const;
  uint64_t mean_us() const;  ///< rounded to nearest
  /// Nearest-rank percentile (1..100): the smallest sample with at least
  /// p % of the samples at or below it.
  uint32_t percentile_us(unsigned p) const;

  /// Bin width: the smallest 1-2-5 step (in µs, ≥ 1) that spans min..max
  /// in at most `max_bins` bins.
  uint32_t bin_width_us(unsigned max_bins) const;
  /// Multi-line report: the four figures, then one line per bin
  /// "  [from, to) ms  count  ####".
  std::string report(unsigned max_bins = 12) const;

 private:
  std::vector<uint32_t> samples_;
};

}  // namespace pcapp
}  // namespace mb2co
