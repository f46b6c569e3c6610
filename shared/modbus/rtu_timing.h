// Character and inter-frame timing of Modbus RTU (serial line spec §2.5.1.1).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace modbus {

/// Bits of one RTU character on the wire: start + 8 data + (parity or second
/// stop) + stop. The spec requires 11 in every mode; 10 (8N1) is what many
/// PC tools use and what the Arduino default serial setup sends.
constexpr uint8_t kRtuCharBits = 11;

/// Above this bit rate the spec fixes t1.5 = 750 µs and t3.5 = 1750 µs.
constexpr uint32_t kFixedTimingAboveBaud = 19200;
constexpr uint32_t kFixedT15Us = 750;
constexpr uint32_t kFixedT35Us = 1750;

/// Invariant: 0 < char_us, t15_us < t35_us (for every baud ≥ 1).
struct RtuTiming {
  uint32_t char_us;  ///< one character on the wire, rounded up
  uint32_t t15_us;   ///< longest silence allowed inside a frame
  uint32_t t35_us;   ///< silence that ends a frame
};

/// Timing for `baud` (bits/s, > 0) and `char_bits` per character (> 0):
/// 1.5 and 3.5 character times rounded up at or below 19200 baud,
/// the fixed 750/1750 µs above.
RtuTiming rtu_timing(uint32_t baud, uint8_t char_bits = kRtuCharBits);

}  // namespace modbus
}  // namespace mb2co
