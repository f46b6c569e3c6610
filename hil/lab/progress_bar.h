// mb2co-lab's progress bar on a terminal. Redraws are rate-limited: a
// 40,000-press run reports progress every 10 presses, and drawing each
// report cost more terminal output than the report itself.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace mb2co {
namespace lab {

class ProgressBar {
 public:
  /// Minimum time between two redraws of the same stage (at most ~10 per second).
  static constexpr uint64_t kMinRedrawNs = 100'000'000;

  /// `out` is not owned; nullptr draws nothing (a bar that is off).
  explicit ProgressBar(std::FILE* out) : out_(out) {}

  /// Progress of `stage` (fraction 0..1) at monotonic time now_ns. Draws
  /// when the stage changes, at the end (fraction >= 1) or when at least
  /// kMinRedrawNs passed since the last drawing and the shown percent changed.
  void show(const std::string& stage, double fraction, uint64_t now_ns);
  /// Erases the bar (before the report is printed).
  void clear();

  /// How often the bar was drawn (for the test of the rate limit).
  uint32_t redraws() const { return redraws_; }

 private:
  std::FILE* out_;
  std::string stage_;
  int percent_ = -1;
  uint64_t drawn_ns_ = 0;
  uint32_t redraws_ = 0;
};

}  // namespace lab
}  // namespace mb2co
