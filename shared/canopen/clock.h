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

}  // namespace mb2co
