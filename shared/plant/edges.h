// Turning sampled signals into events without inventing or losing any:
// rising edges of a polled level, and new events of a wrapping counter that
// another node publishes (STOP2 travels as a counter, seed 000 §10, DESIGN §6).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace plant {

/// Rising edges of a level sampled once per cycle. The first sample after
/// construction or forget() only sets the baseline: a level that was already
/// high (a button held while the link came back) is not an edge.
class RisingEdge {
 public:
  bool update(bool level) {
    const bool edge = known_ && level && !last_;
    last_ = level;
    known_ = true;
    return edge;
  }
  void forget() { known_ = false; }

 private:
  bool last_ = false;
  bool known_ = false;
};

/// New events of a uint16 event counter that wraps 65535 -> 0. A change is
/// (value - last) mod 2^16 new events, so nothing is lost as long as fewer than
/// 32768 events happen between two samples. The first sample is the baseline:
/// events from before this process existed are not ours to act on. A jump of
/// 32768 or more is read as the publisher having restarted its counter (the
/// gateway rebooted and counts from 0 again), not as that many events: it
/// becomes the new baseline, as the firmware does for a rebooted neighbour.
class EventCounter {
 public:
  static const uint16_t kRestartJump = 0x8000;
  uint16_t update(uint16_t value) {
    uint16_t fresh = known_ ? static_cast<uint16_t>(value - last_) : 0u;
    if (fresh >= kRestartJump) fresh = 0;
    last_ = value;
    known_ = true;
    return fresh;
  }

 private:
  uint16_t last_ = 0;
  bool known_ = false;
};

}  // namespace plant
}  // namespace mb2co
