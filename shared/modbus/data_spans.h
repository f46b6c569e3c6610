// Views into the frame buffer through which a RegisterBank reads and writes
// data without a copy: packed bits (Modbus order, LSB of the first byte is the
// first bit) and big-endian 16-bit registers. Plain pointers + counts; they
// are valid only during the RegisterBank call that receives them.
#pragma once
#include <stdint.h>

#include "modbus/protocol.h"

namespace mb2co {
namespace modbus {

/// Read-only packed bits. Invariant: bytes holds packed_bit_bytes(count) bytes.
struct ConstBitSpan {
  const uint8_t* bytes;
  uint16_t count;
  bool get(uint16_t i) const { return packed_bit(bytes, i); }
};

/// Writable packed bits, all zero when handed to the bank (unset bits and the
/// padding of the last byte stay zero as the spec requires).
struct BitSpan {
  uint8_t* bytes;
  uint16_t count;
  bool get(uint16_t i) const { return packed_bit(bytes, i); }
  void set(uint16_t i, bool on) {
    const uint8_t mask = static_cast<uint8_t>(1u << (i & 7u));
    if (on) {
      bytes[i >> 3] = static_cast<uint8_t>(bytes[i >> 3] | mask);
    } else {
      bytes[i >> 3] = static_cast<uint8_t>(bytes[i >> 3] & ~mask);
    }
  }
};

/// Read-only registers. Invariant: bytes holds 2 * count bytes, big-endian.
struct ConstRegisterSpan {
  const uint8_t* bytes;
  uint16_t count;
  uint16_t get(uint16_t i) const { return get_be16(bytes + 2u * i); }
};

/// Writable registers (contents unspecified when handed to the bank).
struct RegisterSpan {
  uint8_t* bytes;
  uint16_t count;
  uint16_t get(uint16_t i) const { return get_be16(bytes + 2u * i); }
  void set(uint16_t i, uint16_t value) { put_be16(bytes + 2u * i, value); }
};

}  // namespace modbus
}  // namespace mb2co
