#include "modbus/rtu_timing.h"

namespace mb2co {
namespace modbus {
namespace {

// ceil(numerator / denominator) without overflow for numerator < 2^32.
uint32_t div_ceil(uint32_t numerator, uint32_t denominator) {
  return numerator / denominator + (numerator % denominator != 0u ? 1u : 0u);
}

}  // namespace

RtuTiming rtu_timing(uint32_t baud, uint8_t char_bits) {
  if (baud == 0u) baud = 1u;  // defined answer for a bad argument
  if (char_bits == 0u) char_bits = kRtuCharBits;
  // char_bits ≤ 255 keeps 7 * bits * 10^6 below 2^32 (1.8e9).
  const uint32_t bit_us_x1e6 = static_cast<uint32_t>(char_bits) * 1000000u;
  RtuTiming t;
  t.char_us = div_ceil(bit_us_x1e6, baud);
  if (baud > kFixedTimingAboveBaud) {
    t.t15_us = kFixedT15Us;
    t.t35_us = kFixedT35Us;
  } else {
    t.t15_us = div_ceil(3u * bit_us_x1e6, 2u * baud);
    t.t35_us = div_ceil(7u * bit_us_x1e6, 2u * baud);
  }
  return t;
}

}  // namespace modbus
}  // namespace mb2co
