// Wrap-safe arithmetic on the 32-bit microsecond clock handed into every
// process(now_us) call. The core never reads a clock itself.
#pragma once
#include <stdint.h>

namespace mb2co {

/// True when `now_us` is at or after `deadline_us`, across the 2^32 µs wrap
/// (valid while the two are less than ~35 minutes apart).
inline bool time_reached(uint32_t now_us, uint32_t deadline_us) {
  return static_cast<int32_t>(now_us - deadline_us) >= 0;
}

/// Microseconds from `now_us` until `deadline_us`, 0 when already reached.
inline uint32_t time_until(uint32_t now_us, uint32_t deadline_us) {
  return time_reached(now_us, deadline_us) ? 0u : deadline_us - now_us;
}

/// The earliest of the deadlines a device's services report, as seen from
/// one `now_us` (next_deadline() of Node, Gateway, the Modbus slave). It
/// keeps the time *until* that deadline, so it is wrap-safe: a deadline
/// already reached counts as now, one ahead by 2^31 µs or more as the
/// longest wait (waking early is always allowed: process() then does
/// nothing). Plain value, no static state.
class NextDeadline {
 public:
  explicit NextDeadline(uint32_t now_us) : now_us_(now_us) {}
  uint32_t now_us() const { return now_us_; }
  /// Something is due at `deadline_us`.
  void at(uint32_t deadline_us) { in(time_until(now_us_, deadline_us)); }
  /// Something is due `delay_us` after now_us().
  void in(uint32_t delay_us) {
    if (delay_us > kLongestUs) delay_us = kLongestUs;
    if (delay_us < until_us_) until_us_ = delay_us;
  }
  /// Something is due now (work left over, a retry).
  void now() { until_us_ = 0; }
  /// False: nothing pending (only an input makes work). Else *at_us = the
  /// earliest deadline, now_us() when something is due already.
  bool result(uint32_t* at_us) const {
    if (until_us_ == kNothing) return false;
    *at_us = now_us_ + until_us_;
    return true;
  }

 private:
  static const uint32_t kLongestUs = 0x7FFFFFFFu;  ///< time_reached()'s horizon
  static const uint32_t kNothing = 0xFFFFFFFFu;
  uint32_t now_us_;
  uint32_t until_us_ = kNothing;
};

}  // namespace mb2co
