#include "segment_line.h"

namespace mb2co {
namespace bridge {

Status SegmentLine::open(const SegmentOptions& o) {
  echo_ = o.echo;
  if (!o.serial.empty()) return port_.open_tty(o.serial, o.baud, modbus::Parity::kNone);
  return port_.create_pty(o.pty_link);
}

bool SegmentLine::write(void* ctx, const uint8_t* data, uint16_t length) {
  SegmentLine& l = *static_cast<SegmentLine*>(ctx);
  if (!l.port_.write(data, length)) {
    ++l.write_failures_;
    return false;
  }
  if (l.echo_ && length <= kMaxMessage) {
    if (l.expected_count_ == kMaxExpected) l.drop_front();  // no echo came back: forget the oldest
    Expected& e = l.expected_[(l.expected_head_ + l.expected_count_) % kMaxExpected];
    for (uint16_t i = 0; i < length; ++i) e.bytes[i] = data[i];
    e.length = static_cast<uint8_t>(length);
    e.written_us = port::monotonic_us();
    ++l.expected_count_;
  }
  return true;
}

void SegmentLine::drop_front() {
  expected_head_ = (expected_head_ + 1u) % kMaxExpected;
  --expected_count_;
  matched_ = 0;
}

void SegmentLine::filter(uint8_t byte, uint32_t stamp_us, void (*on_byte)(void*, uint8_t, uint32_t),
                         void* ctx) {
  while (expected_count_ != 0 && matched_ == 0 &&
         stamp_us - expected_[expected_head_].written_us > kEchoTimeoutUs &&
         static_cast<int32_t>(stamp_us - expected_[expected_head_].written_us) > 0) {
    drop_front();
  }
  if (expected_count_ == 0) {
    on_byte(ctx, byte, stamp_us);
    return;
  }
  const Expected& e = expected_[expected_head_];
  if (byte == e.bytes[matched_]) {
    held_stamps_[matched_++] = stamp_us;
    if (matched_ == e.length) {  // the whole message came back: our echo
      echo_dropped_ += e.length;
      drop_front();
    }
    return;
  }
  // Not our echo (yet): what was held back was someone else's, then this byte
  // (which may begin our echo).
  const size_t held = matched_;
  matched_ = 0;
  for (size_t i = 0; i < held; ++i) on_byte(ctx, e.bytes[i], held_stamps_[i]);
  if (byte == e.bytes[0]) {
    held_stamps_[matched_++] = stamp_us;
    return;
  }
  on_byte(ctx, byte, stamp_us);
}

Status SegmentLine::read(void (*on_byte)(void* ctx, uint8_t byte, uint32_t byte_us), void* ctx) {
  for (;;) {
    uint8_t bytes[256];
    uint32_t stamps[256];
    size_t n = 0;
    Status got = port_.read(bytes, stamps, sizeof bytes, &n);
    if (!got) return got;
    if (n == 0) return Status::ok();
    for (size_t i = 0; i < n; ++i) {
      if (echo_) {
        filter(bytes[i], stamps[i], on_byte, ctx);
      } else {
        on_byte(ctx, bytes[i], stamps[i]);
      }
    }
  }
}

}  // namespace bridge
}  // namespace mb2co
