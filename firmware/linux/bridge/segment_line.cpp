#include "segment_line.h"

namespace mb2co {
namespace bridge {

Status SegmentLine::open(const SegmentOptions& o) {
  echo_ = o.echo;
  if (!o.serial.empty()) return port_.open_tty(o.serial, o.baud, port::Parity::kNone);
  return port_.create_pty(o.pty_link);
}

bool SegmentLine::write(void* ctx, const uint8_t* data, uint16_t length) {
  SegmentLine& l = *static_cast<SegmentLine*>(ctx);
  if (!l.port_.write(data, length)) {
    ++l.write_failures_;
    return false;
  }
  if (l.echo_) {
    for (uint16_t i = 0; i < length; ++i) {
      if (l.expected_count_ == kEchoCapacity) {  // no echo came back: forget the oldest
        l.expected_head_ = (l.expected_head_ + 1u) % kEchoCapacity;
        --l.expected_count_;
      }
      l.expected_[(l.expected_head_ + l.expected_count_) % kEchoCapacity] = data[i];
      ++l.expected_count_;
    }
  }
  return true;
}

bool SegmentLine::is_echo(uint8_t byte) {
  if (!echo_ || expected_count_ == 0) return false;
  if (expected_[expected_head_] != byte) {
    // Not our echo (a collision spoiled it, or the adapter dropped it): stop
    // expecting, so that others' bytes are not eaten.
    expected_count_ = 0;
    return false;
  }
  expected_head_ = (expected_head_ + 1u) % kEchoCapacity;
  --expected_count_;
  ++echo_dropped_;
  return true;
}

Status SegmentLine::read(void (*on_byte)(void* ctx, uint8_t byte, uint32_t byte_us), void* ctx) {
  for (;;) {
    uint8_t bytes[256];
    uint32_t stamps[256];
    size_t n = 0;
    const Status got = port_.read(bytes, stamps, sizeof bytes, &n);
    if (!got) return got;
    if (n == 0) return Status::ok();
    for (size_t i = 0; i < n; ++i) {
      if (!is_echo(bytes[i])) on_byte(ctx, bytes[i], stamps[i]);
    }
  }
}

}  // namespace bridge
}  // namespace mb2co
