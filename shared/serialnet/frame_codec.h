// The message format of CANopen on a byte-oriented serial line (seed 003
// §3.1: an identifier, then up to 8 data bytes), and its byte-fed decoder.
//
// On the line, one message is
//
//   7Eh | id (1 byte; 2 bytes, high first, in the 11-bit set) | length 0..8 |
//   data[length] | CRC low | CRC high
//
// where everything after the 7Eh flag is byte-stuffed: a 7Eh or 7Dh in it is
// sent as 7Dh followed by the byte XOR 20h (HDLC/PPP). The CRC is
// CRC-16/MODBUS (poly 8005h reflected, init FFFFh; crc/crc16.h) over the
// unstuffed id, length and data bytes. For 8-N-1 that is 10 bits per byte.
//
// Why a flag with stuffing and not idle-gap framing like Modbus RTU: a 7Eh
// never occurs inside a message, so a receiver that joined mid-message or was
// fed noise resynchronises at the next flag from the bytes alone, whatever
// their timing. Gap framing needs the receiver to time silences of 1.5 and 3.5
// characters, which ports that hand bytes in bursts (ptys, USB adapters, a
// busy main loop reading an ISR's ring buffer) cannot do (RtuFramer has
// set_check_t15(false) for them), and it costs 3.5 idle characters per
// message where token passing wants messages back to back. The length byte
// ends a message at its last CRC byte (no closing flag to wait for). The
// price: stuffing may double a byte (worst case kMaxEncodedBytes); a garbage
// run that starts with 7Eh passes the CRC with probability 2^-16.
//
// Unused SDO bytes (seed 003 §3.2.2): the adapter (serial_link.h) leaves the
// trailing zero bytes of default-SDO messages off and pads them back; the
// codec itself carries any 0..8 bytes as given.
#pragma once
#include <stdint.h>

#include "serialnet/connection_set.h"

namespace mb2co {
namespace serialnet {

const uint8_t kFlag = 0x7E;       ///< starts every message, never inside one
const uint8_t kEscape = 0x7D;     ///< next byte is XOR kEscapeXor
const uint8_t kEscapeXor = 0x20;  ///< 7Eh → 7Dh 5Eh, 7Dh → 7Dh 5Dh
const uint8_t kMaxDataBytes = 8;
/// Unstuffed content: up to 2 id bytes, length, 8 data, 2 CRC.
const uint8_t kMaxContentBytes = 2 + 1 + kMaxDataBytes + 2;
/// Longest message on the line: the flag and every content byte stuffed.
const uint8_t kMaxEncodedBytes = 1 + 2 * kMaxContentBytes;
/// Bits per byte on the line (8-N-1: start, 8 data, stop).
const uint8_t kBitsPerByte = 10;

/// One message as the data link carries it. Bytes beyond `length` are
/// unspecified.
struct SerialMessage {
  uint16_t id;  ///< serial identifier, < 2^id_bits of the connection set
  uint8_t length;
  uint8_t data[kMaxDataBytes];
};

/// Identifier bytes of `set` on the line (1 for 6/7/8 bits, 2 for 11).
inline uint8_t id_bytes(const ConnectionSet& set) {
  return set.id_bits > 8 ? 2 : 1;
}

/// Writes `m` as it goes on the line into out[0, n) and returns n (at most
/// kMaxEncodedBytes). 0, with nothing written, when `m` is not valid for
/// `set` (id too wide, length > 8) or `capacity` is too small for it.
uint8_t encode(const ConnectionSet& set, const SerialMessage& m, uint8_t* out, uint8_t capacity);

/// Time one byte takes on the line at `baud` (kBitsPerByte bits), rounded up.
uint32_t byte_time_us(uint32_t baud);

/// Receives messages from bytes with their time stamps. Owns no buffer
/// beyond itself (about 30 bytes); one context only.
///
/// `byte_us` is when the byte had been received completely (never earlier);
/// the stamp of a message is that of its last CRC byte. When max_gap_us is
/// not 0, a silence longer than that between two bytes of one message drops
/// the message (a talker that died mid-message) instead of waiting for a
/// flag; the stamps may go backwards (counted as no silence).
class Decoder {
 public:
  /// What a byte completed. Everything but kNothing and kMessage is counted.
  enum Result : uint8_t {
    kNothing,    ///< no message ended with this byte
    kMessage,    ///< message() holds a new message, CRC right
    kBadCrc,     ///< a complete message with a wrong CRC: dropped
    kBadLength,  ///< a length byte > 8: dropped, hunting for the next flag
    kBadId,      ///< id wider than the set (11-bit set: high byte > 7)
    kTruncated,  ///< a flag or bad escape inside a message, or max_gap_us passed
  };

  explicit Decoder(const ConnectionSet& set, uint32_t max_gap_us = 0) : set_(set), max_gap_us_(max_gap_us) {}

  Result push(uint8_t byte, uint32_t byte_us);
  /// The last kMessage; valid until the next push().
  const SerialMessage& message() const { return msg_; }
  uint32_t message_us() const { return msg_us_; }
  const ConnectionSet& connection_set() const { return set_; }

  /// Counters that never decrement (saturate at 0xFFFF).
  struct Counters {
    uint16_t messages;
    uint16_t bad_crc;
    uint16_t bad_length;
    uint16_t bad_id;
    uint16_t truncated;
    uint16_t skipped_bytes;  ///< bytes outside any message (noise, a tail)
  };
  const Counters& counters() const { return counters_; }

 private:
  Result start();
  Result content(uint8_t byte, uint32_t byte_us);
  Result fail(Result r);

  ConnectionSet set_;
  uint32_t max_gap_us_;
  uint32_t last_us_ = 0;
  uint32_t msg_us_ = 0;
  Counters counters_ = {};
  SerialMessage msg_ = {};
  uint8_t raw_[kMaxContentBytes] = {};
  uint8_t got_ = 0;       ///< content bytes in raw_
  uint8_t expected_ = 0;  ///< content bytes of this message, 0 until the length byte
  bool in_message_ = false;
  bool escaped_ = false;
};

}  // namespace serialnet
}  // namespace mb2co
