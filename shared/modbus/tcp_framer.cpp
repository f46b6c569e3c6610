#include "modbus/tcp_framer.h"

#include <string.h>

#include "crc/crc16.h"

namespace mb2co {
namespace modbus {

MbapHeader read_mbap_header(const uint8_t* p) {
  return MbapHeader{get_be16(p), get_be16(p + 2), get_be16(p + 4), p[6]};
}

void write_mbap_header(uint8_t* p, const MbapHeader& h) {
  put_be16(p, h.transaction);
  put_be16(p + 2, h.protocol);
  put_be16(p + 4, h.length);
  p[6] = h.unit;
}

uint16_t mbap_frame_length(const uint8_t* p) {
  const uint16_t length = get_be16(p + 4);
  if (length < kMinMbapLength || length > kMaxMbapLength) return 0;
  return static_cast<uint16_t>(6u + length);
}

uint16_t MbapReceiver::wanted() const {
  if (have_ < kMbapHeaderBytes) return static_cast<uint16_t>(kMbapHeaderBytes - have_);
  return static_cast<uint16_t>(6u + header_.length - have_);
}

MbapReceiver::Result MbapReceiver::push(const uint8_t* data, uint16_t n) {
  const uint16_t room = wanted();
  if (n > room) n = room;  // the contract says n <= wanted(): never beyond the buffer
  memcpy(buf_ + have_, data, n);
  have_ = static_cast<uint16_t>(have_ + n);
  if (have_ < kMbapHeaderBytes) return Result::kNeedMore;
  if (have_ == kMbapHeaderBytes) {
    header_ = read_mbap_header(buf_);
    if (mbap_frame_length(buf_) == 0u) return Result::kBadLength;
  }
  if (wanted() != 0u) return Result::kNeedMore;
  return header_.protocol == kMbapProtocolModbus ? Result::kRequest : Result::kForeign;
}

uint16_t MbapReceiver::frame_response(uint16_t pdu_length) {
  const MbapHeader h = {header_.transaction, kMbapProtocolModbus, static_cast<uint16_t>(pdu_length + 1u),
                        header_.unit};
  write_mbap_header(buf_, h);
  return static_cast<uint16_t>(kMbapHeaderBytes + pdu_length);
}

uint16_t mbap_from_rtu(uint8_t* out, uint16_t capacity, const uint8_t* rtu, uint16_t rtu_length,
                       uint16_t transaction) {
  if (rtu_length < 2u + kCrcBytes) return 0;
  const uint16_t pdu_length = static_cast<uint16_t>(rtu_length - 1u - kCrcBytes);
  const uint16_t length = static_cast<uint16_t>(kMbapHeaderBytes + pdu_length);
  if (pdu_length > kMaxPduBytes || length > capacity) return 0;
  const MbapHeader h = {transaction, kMbapProtocolModbus, static_cast<uint16_t>(pdu_length + 1u), rtu[0]};
  write_mbap_header(out, h);
  memcpy(out + kMbapHeaderBytes, rtu + 1, pdu_length);
  return length;
}

uint16_t rtu_from_mbap(uint8_t* out, uint16_t capacity, const uint8_t* frame, uint16_t frame_length) {
  if (frame_length < kMbapHeaderBytes || mbap_frame_length(frame) != frame_length) return 0;
  const MbapHeader h = read_mbap_header(frame);
  if (h.protocol != kMbapProtocolModbus) return 0;
  const uint16_t pdu_length = static_cast<uint16_t>(h.length - 1u);
  if (1u + pdu_length + kCrcBytes > capacity) return 0;
  out[0] = h.unit;
  memcpy(out + 1, frame + kMbapHeaderBytes, pdu_length);
  return append_crc(out, static_cast<uint16_t>(1u + pdu_length));
}

}  // namespace modbus
}  // namespace mb2co
