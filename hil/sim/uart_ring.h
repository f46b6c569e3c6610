// The Arduino's serial receive side in virtual time: the characters a loop
// pass takes from the link, what a full receive ring drops, and the bytes of
// the request being received (for the pass's cost, NodeTiming).
#pragma once
#include <stdint.h>

#include <vector>

#include "sim/event_queue.h"
#include "sim/serial_link.h"

namespace mb2co {
namespace sim {

class UartRing {
 public:
  /// `capacity`: characters the ring holds between two passes (more are
  /// dropped and counted); a silence of t3.5 + one character at `baud`
  /// starts a new request.
  UartRing(uint32_t baud, uint32_t capacity);

  /// Hands every character complete by `t` to `deliver` in order, except
  /// those beyond the ring's capacity; returns how many were handed.
  template <class Deliver>
  uint32_t take(UartChannel& rx, SimNs t, Deliver&& deliver) {
    SerialChar c;
    uint32_t taken = 0;
    uint32_t handed = 0;
    while (rx.take(t, &c)) {
      if (++taken > capacity_) {  // the ring was full: dropped
        ++overruns_;
        continue;
      }
      if (c.end_ns - last_char_ns_ > frame_gap_ns_ || frame_.size() >= 256) frame_.clear();
      frame_.push_back(c.byte);
      last_char_ns_ = c.end_ns;
      ++handed;
      deliver(c);
    }
    return handed;
  }
  /// The characters of the request being received (since the last gap).
  const std::vector<uint8_t>& request() const { return frame_; }
  void clear_request() { frame_.clear(); }
  uint64_t overruns() const { return overruns_; }

 private:
  uint32_t capacity_;
  SimNs frame_gap_ns_;  ///< a silence this long starts a new frame
  SimNs last_char_ns_ = 0;
  std::vector<uint8_t> frame_;
  uint64_t overruns_ = 0;
};

}  // namespace sim
}  // namespace mb2co
