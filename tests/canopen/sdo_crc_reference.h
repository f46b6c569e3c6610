// The CiA 301 block-transfer CRC (CRC-16/XMODEM: polynomial 1021h, initial
// value 0, no reflection), written independently of canopen::sdo_crc16 so a
// test compares the implementation with the definition, not with itself.
#pragma once
#include <stdint.h>

#include <vector>

namespace mb2co {
namespace test {

inline uint16_t crc_ref(const std::vector<uint8_t>& data) {
  uint32_t crc = 0;
  for (uint8_t byte : data) {
    crc ^= static_cast<uint32_t>(byte) << 8;
    for (int bit = 0; bit < 8; ++bit) {
      crc <<= 1;
      if (crc & 0x10000u) crc ^= 0x11021u;
    }
  }
  return static_cast<uint16_t>(crc);
}

}  // namespace test
}  // namespace mb2co
