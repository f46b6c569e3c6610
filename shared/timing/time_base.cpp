#include "timing/time_base.h"

namespace mb2co {
namespace timing {

// ticks / bitrate is whole microseconds; the remainder (< bitrate ≤ 10^6)
// times 1000 fits easily, so no intermediate product can overflow.
uint64_t ticks_to_ns_floor(uint64_t ticks, uint32_t bitrate_bps) {
  const uint64_t us = ticks / bitrate_bps;
  const uint64_t rem = ticks % bitrate_bps;
  return us * 1000u + (rem * 1000u) / bitrate_bps;
}

uint64_t ticks_to_ns_ceil(uint64_t ticks, uint32_t bitrate_bps) {
  const uint64_t us = ticks / bitrate_bps;
  const uint64_t rem = ticks % bitrate_bps;
  return us * 1000u + (rem * 1000u + bitrate_bps - 1u) / bitrate_bps;
}

}  // namespace timing
}  // namespace mb2co
