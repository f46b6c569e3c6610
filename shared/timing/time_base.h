// The integer time unit of the CAN analysis. One tick is 1/(bitrate · 10^6)
// of a second, so a bit (10^6 ticks) and a microsecond (bitrate ticks) are
// both whole numbers at any bit rate: every sum, ceiling and comparison of the
// response-time analysis is exact, and rounding happens only on output.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace timing {

/// Ticks in one bit time, whatever the bit rate.
constexpr uint64_t kTicksPerBit = 1000000u;

/// Classic CAN tops out at 1 Mbit/s; the bound keeps every tick count of a
/// 32-bit microsecond value below 2^52 (room for sums without overflow).
constexpr uint32_t kMaxBitrateBps = 1000000u;

/// True for 1 ≤ bitrate ≤ kMaxBitrateBps.
inline bool bitrate_valid(uint32_t bitrate_bps) {
  return bitrate_bps >= 1u && bitrate_bps <= kMaxBitrateBps;
}

/// `us` microseconds in ticks at `bitrate_bps` (valid bit rate required).
inline uint64_t us_to_ticks(uint64_t us, uint32_t bitrate_bps) {
  return us * bitrate_bps;
}

/// `bits` bit times in ticks.
inline uint64_t bits_to_ticks(uint64_t bits) {
  return bits * kTicksPerBit;
}

/// Ticks to nanoseconds, rounded up (for upper bounds: never optimistic).
/// Exact for every bit rate that divides 10^9 (all CiA 301 rates).
uint64_t ticks_to_ns_ceil(uint64_t ticks, uint32_t bitrate_bps);

/// Ticks to nanoseconds, rounded down (for lower bounds).
uint64_t ticks_to_ns_floor(uint64_t ticks, uint32_t bitrate_bps);

/// Ticks to whole bit times, rounded up.
inline uint64_t ticks_to_bits_ceil(uint64_t ticks) {
  return (ticks + kTicksPerBit - 1u) / kTicksPerBit;
}

/// Transmission time of `bits` at `bitrate_bps` in ns, rounded up:
/// 130 bits at 50 kbit/s = 2,600,000 ns (seed 000 §2.10).
inline uint64_t bits_to_ns_ceil(uint64_t bits, uint32_t bitrate_bps) {
  return ticks_to_ns_ceil(bits_to_ticks(bits), bitrate_bps);
}

}  // namespace timing
}  // namespace mb2co
