// The frames a node has waiting for its window: a small bounded queue kept
// in CAN priority order (lowest id first, first come first served among equal
// ids, so SDO segments and repeated PDOs keep their order). No heap.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace serialnet {

class TxQueue {
 public:
  /// 8 frames: a node's boot-up or heartbeat, EMCY, up to 4 TPDOs and an SDO
  /// response fit at once (14 bytes each: 112 bytes of RAM on the Uno).
  static const uint8_t kCapacity = 8;

  /// False when full (nothing changes).
  bool push(const CanFrame& f);
  /// When a frame with f.id waits already, f replaces it in its place (the
  /// newest process data wins: it leaves in the same window); else push().
  bool replace_or_push(const CanFrame& f);
  bool empty() const { return count_ == 0; }
  uint8_t size() const { return count_; }
  /// The highest-priority frame (lowest id); only when !empty().
  const CanFrame& front() const { return frames_[0]; }
  void pop_front();
  void clear() { count_ = 0; }

 private:
  CanFrame frames_[kCapacity];  ///< [0, count_) sorted by id, stable
  uint8_t count_ = 0;
};

}  // namespace serialnet
}  // namespace mb2co
