#include "serialnet/tx_queue.h"

namespace mb2co {
namespace serialnet {

bool TxQueue::push(const CanFrame& f) {
  if (count_ == kCapacity) return false;
  uint8_t at = count_;
  // After every frame with an id <= f.id: equal ids stay in arrival order.
  while (at > 0 && frames_[at - 1].id > f.id) {
    frames_[at] = frames_[at - 1];
    --at;
  }
  frames_[at] = f;
  ++count_;
  return true;
}

bool TxQueue::replace_or_push(const CanFrame& f) {
  for (uint8_t i = 0; i < count_; ++i) {
    if (frames_[i].id == f.id) {
      frames_[i] = f;
      return true;
    }
  }
  return push(f);
}

void TxQueue::pop_front() {
  if (count_ == 0) return;
  --count_;
  for (uint8_t i = 0; i < count_; ++i) frames_[i] = frames_[i + 1];
}

}  // namespace serialnet
}  // namespace mb2co
