// Reconnection delays after a lost serial link: first_ms, doubling up to
// max_ms, back to first_ms once the link is up again.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace pcapp {

class Backoff {
 public:
  /// 0 < first_ms <= max_ms.
  Backoff(uint32_t first_ms, uint32_t max_ms) : first_ms_(first_ms), max_ms_(max_ms), next_ms_(first_ms) {}
  /// The delay before the next attempt; each call doubles the following one.
  uint32_t next_ms() {
    const uint32_t d = next_ms_;
    next_ms_ = next_ms_ > max_ms_ / 2 ? max_ms_ : next_ms_ * 2;
    return d;
  }
  void reset() { next_ms_ = first_ms_; }

 private:
  uint32_t first_ms_;
  uint32_t max_ms_;
  uint32_t next_ms_;
};

}  // namespace pcapp
}  // namespace mb2co
