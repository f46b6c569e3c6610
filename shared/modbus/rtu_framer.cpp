#include "modbus/rtu_framer.h"

#include "crc/crc16.h"

namespace mb2co {
namespace modbus {
namespace {

// Microseconds from `from_us` to `to_us`, 0 when `to_us` is earlier.
uint32_t elapsed_us(uint32_t from_us, uint32_t to_us) {
  const int32_t d = static_cast<int32_t>(to_us - from_us);
  return d > 0 ? static_cast<uint32_t>(d) : 0u;
}

}  // namespace

void RtuFramer::begin(uint32_t now_us) {
  state_ = State::kInitial;
  last_us_ = now_us;
  length_ = 0;
}

uint32_t RtuFramer::silence_before(uint32_t byte_us) const {
  const uint32_t gap = elapsed_us(last_us_, byte_us);
  return gap > timing_.char_us ? gap - timing_.char_us : 0u;
}

bool RtuFramer::t35_passed(uint32_t now_us) const {
  return elapsed_us(last_us_, now_us) >= timing_.t35_us;
}

bool RtuFramer::frame_due(uint32_t now_us) const {
  return state_ == State::kReceiving && t35_passed(now_us);
}

bool RtuFramer::frame_due_before(uint32_t byte_us) const {
  return state_ == State::kReceiving && silence_before(byte_us) >= timing_.t35_us;
}

void RtuFramer::push_char(uint8_t byte, uint32_t byte_us, bool error) {
  if (state_ == State::kInitial) {
    // Still waiting for the line to be quiet: the character is the tail of a
    // frame we joined in the middle; the wait starts again.
    if (silence_before(byte_us) < timing_.t35_us) {
      last_us_ = byte_us;
      return;
    }
    state_ = State::kIdle;
  }
  if (state_ == State::kIdle) {
    state_ = State::kReceiving;
    length_ = 0;
    flags_ = 0;
  } else if (!ignore_t15_ && silence_before(byte_us) > timing_.t15_us) {
    flags_ |= kFlagT15;
  }
  if (error) flags_ |= kFlagCharError;
  if (length_ < capacity_) {
    buf_[length_++] = byte;
  } else {
    flags_ |= kFlagOverrun;
  }
  last_us_ = byte_us;
}

void RtuFramer::tick(uint32_t now_us) {
  if (state_ == State::kInitial && t35_passed(now_us)) {
    state_ = State::kIdle;
  }
}

FrameStatus RtuFramer::finish() {
  state_ = State::kIdle;
  if (flags_ & kFlagOverrun) return FrameStatus::kOverrun;
  if (flags_ & kFlagCharError) return FrameStatus::kCharError;
  if (flags_ & kFlagT15) return FrameStatus::kT15Violation;
  if (length_ < kMinAduBytes) return FrameStatus::kTooShort;
  return crc_ok(buf_, length_) ? FrameStatus::kOk : FrameStatus::kBadCrc;
}

bool RtuFramer::deadline(uint32_t& at_us) const {
  if (state_ == State::kIdle) return false;
  at_us = last_us_ + timing_.t35_us;
  return true;
}

}  // namespace modbus
}  // namespace mb2co
