#include "latency_stats.h"

#include <algorithm>
#include <cstdio>

namespace mb2co {
namespace pcapp {

uint32_t LatencyStats::min_us() const {
  return *std::min_element(samples_.begin(), samples_.end());
}
uint32_t LatencyStats::max_us() const {
  return *std::max_element(samples_.begin(), samples_.end());
}

uint64_t LatencyStats::mean_us() const {
  uint64_t sum = 0;
  for (uint32_t s : samples_) sum += s;
  return (sum + samples_.size() / 2) / samples_.size();
}

uint32_t LatencyStats::percentile_us(unsigned p) const {
  std::vector<uint32_t> sorted = samples_;
  std::sort(sorted.begin(), sorted.end());
  const size_t n = sorted.size();
  size_t rank = (static_cast<size_t>(p) * n + 99) / 100;  // ceil(p/100 * n), 1-based
  if (rank == 0) rank = 1;
  return sorted[rank - 1];
}

uint32_t LatencyStats::bin_width_us(unsigned max_bins) const {
  const uint64_t span = uint64_t{max_us()} - min_us() + 1;
  for (uint64_t decade = 1;; decade *= 10) {
    for (uint64_t m : {1u, 2u, 5u}) {
      const uint64_t w = m * decade;
      if ((span + w - 1) / w <= max_bins) return static_cast<uint32_t>(w);
    }
  }
}

std::string LatencyStats::report(unsigned max_bins) const {
  if (samples_.empty()) return "no presses measured\n";
  char line[160];
  std::snprintf(line, sizeof line, "presses %zu  min %.3f ms  mean %.3f ms  p99 %.3f ms  max %.3f ms\n",
                samples_.size(), min_us() / 1000.0, static_cast<double>(mean_us()) / 1000.0,
                percentile_us(99) / 1000.0, max_us() / 1000.0);
  std::string out = line;
  const uint32_t w = bin_width_us(max_bins);
  const uint32_t first = min_us() / w * w;
  const size_t bins = (max_us() - first) / w + 1;
  std::vector<size_t> counts(bins, 0);
  for (uint32_t s : samples_) ++counts[(s - first) / w];
  const size_t top = *std::max_element(counts.begin(), counts.end());
  for (size_t b = 0; b < bins; ++b) {
    const uint64_t from = first + uint64_t{w} * b;
    std::snprintf(line, sizeof line, "  [%8.3f, %8.3f) ms %6zu  ", static_cast<double>(from) / 1000.0,
                  static_cast<double>(from + w) / 1000.0, counts[b]);
    out += line;
    out += std::string((counts[b] * 40 + top - 1) / top, '#') + "\n";
  }
  return out;
}

}  // namespace pcapp
}  // namespace mb2co
