// TIME_OF_DAY (CiA 301 §7.1.6.5), the payload of a TIME frame: its 6 bytes
// and the network clock's µs scale. Header-only and switch-free: the
// master (a TIME producer on the host) and the node's TIME service
// (time_stamp.h, only where the profile has TIME) share it, and an image
// that uses none of it carries no byte of it.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace canopen {

/// 28 bits of ms after midnight, days since 1984-01-01 (the CANopen epoch).
struct TimeOfDay {
  uint32_t ms;    ///< 0 .. kMsPerDay - 1
  uint16_t days;  ///< since 1984-01-01
};
const uint32_t kMsPerDay = 86400000u;
const uint8_t kTimeFrameLength = 6;
/// The TIME frame's COB-ID by default (CiA 301: 1012h = 100h).
const uint16_t kTimeCobIdDefault = 0x100;

/// The network clock's reading (µs since 1984-01-01, mod 2^32) at `t`.
/// One day is 86,400,000,000 µs = 500,654,080 mod 2^32.
inline uint32_t network_us_of(const TimeOfDay& t) {
  return static_cast<uint32_t>(t.days) * 500654080u + t.ms * 1000u;
}

/// The 6 bytes of a TIME frame: little-endian UNSIGNED32 ms with the top 4
/// bits 0, UNSIGNED16 days.
inline void encode_time_of_day(const TimeOfDay& t, uint8_t* out6) {
  const uint32_t ms = t.ms & 0x0FFFFFFFu;
  for (uint8_t i = 0; i < 4; ++i) out6[i] = static_cast<uint8_t>(ms >> (8 * i));
  out6[4] = static_cast<uint8_t>(t.days);
  out6[5] = static_cast<uint8_t>(t.days >> 8);
}

/// The TimeOfDay of a TIME frame's 6 bytes; bits 28-31 of the ms are
/// reserved and masked (CANopenNode's CO_TIME.c masks them too).
inline TimeOfDay decode_time_of_day(const uint8_t* in6) {
  TimeOfDay t;
  t.ms = (static_cast<uint32_t>(in6[0]) | static_cast<uint32_t>(in6[1]) << 8 |
          static_cast<uint32_t>(in6[2]) << 16 | static_cast<uint32_t>(in6[3]) << 24) &
         0x0FFFFFFFu;
  t.days = static_cast<uint16_t>(in6[4] | (in6[5] << 8));
  return t;
}

}  // namespace canopen
}  // namespace mb2co
