// CRC-16/MODBUS (poly 0xA001 reflected, init 0xFFFF), serial line spec §6.2.2.
// Sent low byte first. One routine for every user in an image: Modbus RTU
// ADUs (shared/modbus), the saved parameters (canopen/param_storage.h) and
// the frames of a serial CANopen segment (shared/serialnet), so none of them
// depends on another for it. A 16-entry nibble table (32 bytes, in flash on the AVR)
// instead of the usual 256-entry table: an Uno has 2 KB of RAM.
#pragma once
#include <stdint.h>

namespace mb2co {

constexpr uint16_t kCrcInit = 0xFFFF;
constexpr uint8_t kCrc16Bytes = 2;  ///< the CRC's bytes at the end of a frame

/// CRC of `length` bytes, continuing from `crc` (chain calls for split buffers).
uint16_t crc16(const uint8_t* data, uint16_t length, uint16_t crc = kCrcInit);

/// Appends the CRC of data[0, length) at data[length], low byte first.
/// The caller guarantees room for two more bytes. Returns length + 2.
uint16_t append_crc(uint8_t* data, uint16_t length);

/// True when the last two bytes of adu[0, length) are the CRC of the rest.
/// False for length < 3.
bool crc_ok(const uint8_t* adu, uint16_t length);

}  // namespace mb2co
