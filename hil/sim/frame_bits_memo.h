// The exact stuffed length of the frames a simulated bus sends, remembered:
// timing::frame_bits_exact walks every bit of a frame (CRC and stuffing,
// ~860 instructions), and a line sends the same frames again and again
// (heartbeats, SYNC, a TPDO whose value has not changed). A remembered
// answer is the function's own: a slot is used only for a frame equal in
// everything frame_bits_exact reads (id, flags, dlc, the data bytes dlc
// counts), so the bus times every frame as before.
#pragma once
#include <stdint.h>
#include <string.h>

#include "canopen/can_frame.h"
#include "timing/can_bits.h"

namespace mb2co {
namespace sim {

class FrameBitsMemo {
 public:
  FrameBitsMemo() { memset(slots_, 0, sizeof slots_); }

  /// timing::frame_bits_exact(frame), remembered by the frame's content.
  timing::ExactFrameBits of(const CanFrame& f) {
    const uint8_t n = f.dlc < 8 ? f.dlc : 8;  // bytes beyond the 8th are never on the wire
    uint32_t h = f.id * 0x9E3779B1u + static_cast<uint32_t>(f.dlc << 8 | f.flags);
    for (uint8_t i = 0; i < n; ++i) h = h * 31u + f.data[i];
    Slot& s = slots_[(h >> 8) % kSlots];
    if (!s.used || s.frame.id != f.id || s.frame.dlc != f.dlc || s.frame.flags != f.flags ||
        memcmp(s.frame.data, f.data, n) != 0) {
      s.frame = f;
      s.bits = timing::frame_bits_exact(f);
      s.used = true;
    }
    return s.bits;
  }

 private:
  /// A slot holds the last frame that hashed to it.
  struct Slot {
    CanFrame frame;
    timing::ExactFrameBits bits;
    bool used;
  };
  static const uint32_t kSlots = 64;
  Slot slots_[kSlots];
};

}  // namespace sim
}  // namespace mb2co
