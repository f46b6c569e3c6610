// Modbus application-protocol constants (Modbus Application Protocol V1.1b3,
// Modbus over Serial Line V1.02): function codes, exception codes, quantity
// limits, diagnostics sub-functions, and big-endian field access.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace modbus {

/// Exception codes a server returns (application protocol §7). kNone means
/// "no exception": never sent on the wire.
enum class Exception : uint8_t {
  kNone = 0x00,
  kIllegalFunction = 0x01,      ///< function or sub-function not supported
  kIllegalDataAddress = 0x02,   ///< some address of the request is not accessible
  kIllegalDataValue = 0x03,     ///< malformed request: quantity, byte count, length
  kServerDeviceFailure = 0x04,  ///< execution failed (value rejected, device error)
  kServerDeviceBusy = 0x06,  ///< busy with a long request (FC 2Bh/0Dh: a remote transfer runs; a 1010h save)
};

/// Function codes handled by this library.
namespace fc {
enum : uint8_t {
  kReadCoils = 0x01,
  kReadDiscreteInputs = 0x02,
  kReadHoldingRegisters = 0x03,
  kReadInputRegisters = 0x04,
  kWriteSingleCoil = 0x05,
  kWriteSingleRegister = 0x06,
  kDiagnostics = 0x08,
  kWriteMultipleCoils = 0x0F,
  kWriteMultipleRegisters = 0x10,
  kReadWriteMultipleRegisters = 0x17,
  kEncapsulatedInterface = 0x2B,  ///< with MEI type 0x0E: read device identification
  kExceptionFlag = 0x80,          ///< set in the function byte of an exception response
};
}  // namespace fc

/// MEI type of "Read Device Identification" inside function 0x2B.
constexpr uint8_t kMeiReadDeviceId = 0x0E;
/// MEI type of the CANopen General Reference (modbus/network_pdu.h).
constexpr uint8_t kMeiCanopenReference = 0x0D;

/// Diagnostics (function 0x08) sub-function codes, serial line spec §6.1.
namespace diag {
enum : uint16_t {
  kReturnQueryData = 0x00,
  kRestartCommunications = 0x01,
  kReturnDiagnosticRegister = 0x02,
  kForceListenOnly = 0x04,
  kClearCounters = 0x0A,
  kBusMessageCount = 0x0B,
  kBusCommErrorCount = 0x0C,
  kBusExceptionCount = 0x0D,
  kServerMessageCount = 0x0E,
  kServerNoResponseCount = 0x0F,
  kServerNakCount = 0x10,
  kServerBusyCount = 0x11,
  kBusCharOverrunCount = 0x12,
  kClearOverrun = 0x14,
};
}  // namespace diag

/// Quantity limits (inclusive upper bounds; the lower bound is always 1).
/// They are what fits into one 256-byte RTU ADU.
constexpr uint16_t kMaxReadBits = 2000;           ///< FC 01, 02
constexpr uint16_t kMaxReadRegisters = 125;       ///< FC 03, 04, and the read part of 17
constexpr uint16_t kMaxWriteCoils = 1968;         ///< FC 0F
constexpr uint16_t kMaxWriteRegisters = 123;      ///< FC 10
constexpr uint16_t kMaxReadWriteWriteRegs = 121;  ///< write part of FC 17

/// RTU addressing: 0 broadcast, 1..247 individual, 248..255 reserved.
constexpr uint8_t kBroadcastAddress = 0;
constexpr uint8_t kMaxServerAddress = 247;

/// RTU application data unit: address + PDU (≤ 253 bytes) + CRC.
constexpr uint16_t kMaxAduBytes = 256;
constexpr uint16_t kMinAduBytes = 4;  ///< address, function, CRC
constexpr uint16_t kCrcBytes = 2;

/// FC 05 coil values: anything else is exception 03.
constexpr uint16_t kCoilOn = 0xFF00;
constexpr uint16_t kCoilOff = 0x0000;

/// Big-endian 16-bit field at p (Modbus byte order for addresses/registers).
inline uint16_t get_be16(const uint8_t* p) {
  return static_cast<uint16_t>((static_cast<uint16_t>(p[0]) << 8) | p[1]);
}
inline void put_be16(uint8_t* p, uint16_t v) {
  p[0] = static_cast<uint8_t>(v >> 8);
  p[1] = static_cast<uint8_t>(v & 0xFFu);
}

/// Bytes needed for `count` packed bits (LSB of the first byte is the first bit).
inline uint16_t packed_bit_bytes(uint16_t count) {
  return static_cast<uint16_t>((count + 7u) / 8u);
}

/// Bit `i` of a packed bit field (Modbus order: LSB of the first byte first).
inline bool packed_bit(const uint8_t* bytes, uint16_t i) {
  return ((static_cast<unsigned>(bytes[i >> 3]) >> (i & 7u)) & 1u) != 0u;
}

}  // namespace modbus
}  // namespace mb2co
