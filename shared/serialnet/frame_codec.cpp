#include "serialnet/frame_codec.h"

#include <string.h>

#include "crc/crc16.h"

namespace mb2co {
namespace serialnet {
namespace {

inline void bump(uint16_t& counter) {
  if (counter != 0xFFFFu) ++counter;
}

// Appends `byte` stuffed; false when it does not fit.
bool put(uint8_t byte, uint8_t* out, uint8_t capacity, uint8_t* n) {
  const bool special = byte == kFlag || byte == kEscape;
  if (*n + (special ? 2u : 1u) > capacity) return false;
  if (special) {
    out[(*n)++] = kEscape;
    byte = static_cast<uint8_t>(byte ^ kEscapeXor);
  }
  out[(*n)++] = byte;
  return true;
}

}  // namespace

uint8_t encode(const ConnectionSet& set, const SerialMessage& m, uint8_t* out, uint8_t capacity) {
  if ((m.id >> set.id_bits) != 0 || m.length > kMaxDataBytes || capacity == 0) return 0;
  uint8_t content[kMaxContentBytes];
  uint8_t c = 0;
  if (id_bytes(set) == 2) content[c++] = static_cast<uint8_t>(m.id >> 8);
  content[c++] = static_cast<uint8_t>(m.id);
  content[c++] = m.length;
  memcpy(content + c, m.data, m.length);
  c = append_crc(content, static_cast<uint8_t>(c + m.length)) & 0xFFu;
  uint8_t n = 0;
  out[n++] = kFlag;
  for (uint8_t i = 0; i < c; ++i) {
    if (!put(content[i], out, capacity, &n)) return 0;
  }
  return n;
}

uint32_t byte_time_us(uint32_t baud) {
  if (baud == 0) return 0;
  return (kBitsPerByte * 1000000u + baud - 1u) / baud;
}

Decoder::Result Decoder::fail(Result r) {
  in_message_ = false;
  escaped_ = false;
  if (r == kBadCrc) bump(counters_.bad_crc);
  if (r == kBadLength) bump(counters_.bad_length);
  if (r == kBadId) bump(counters_.bad_id);
  if (r == kTruncated) bump(counters_.truncated);
  return r;
}

Decoder::Result Decoder::start() {
  in_message_ = true;
  escaped_ = false;
  got_ = 0;
  expected_ = 0;
  return kNothing;
}

Decoder::Result Decoder::push(uint8_t byte, uint32_t byte_us) {
  const uint32_t gap_us = byte_us - last_us_;
  const bool gap = max_gap_us_ != 0 && static_cast<int32_t>(gap_us) > 0 && gap_us > max_gap_us_;
  last_us_ = byte_us;
  Result r = kNothing;
  if (in_message_ && gap) r = fail(kTruncated);
  if (byte == kFlag) {
    // A flag always starts a message: whatever was in progress is cut short.
    if (in_message_) r = fail(kTruncated);
    start();
    return r;
  }
  if (!in_message_) {
    bump(counters_.skipped_bytes);
    return r;
  }
  return content(byte, byte_us);
}

Decoder::Result Decoder::content(uint8_t byte, uint32_t byte_us) {
  if (escaped_) {
    escaped_ = false;
    byte = static_cast<uint8_t>(byte ^ kEscapeXor);
    if (byte != kFlag && byte != kEscape) return fail(kTruncated);  // not a stuffed byte
  } else if (byte == kEscape) {
    escaped_ = true;
    return kNothing;
  }
  raw_[got_++] = byte;
  const uint8_t ids = id_bytes(set_);
  if (got_ == 1 && ids == 2 && byte > 0x07u) return fail(kBadId);
  if (got_ == ids + 1u) {
    if (byte > kMaxDataBytes) return fail(kBadLength);
    expected_ = static_cast<uint8_t>(ids + 1u + byte + 2u);
  }
  if (expected_ == 0 || got_ < expected_) return kNothing;
  in_message_ = false;
  if (!crc_ok(raw_, got_)) return fail(kBadCrc);
  const uint16_t id = ids == 2 ? static_cast<uint16_t>((raw_[0] << 8) | raw_[1]) : raw_[0];
  if ((id >> set_.id_bits) != 0) return fail(kBadId);
  msg_.id = id;
  msg_.length = raw_[ids];
  memcpy(msg_.data, raw_ + ids + 1, msg_.length);
  msg_us_ = byte_us;
  bump(counters_.messages);
  return kMessage;
}

}  // namespace serialnet
}  // namespace mb2co
