// The gateway's view of the CANopen network: the NMT state and the time of
// the last heartbeat (or boot-up) of every node it hears, fed from the frames
// the node receives. What FC 2Bh/0Dh's network view service reports
// (docs/gateway-network.md). Plain data, no heap; capacity at compile time.
// All zero is empty: members have no initialisers, the owner value-
// initialises the view (NetworkServiceState: one zero-fill on the Uno).
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace gateway {

/// Nodes the view holds: every possible node on Linux, a few on the Uno.
#ifdef __AVR__
constexpr uint8_t kNetViewNodes = 4;
#else
constexpr uint8_t kNetViewNodes = 127;
#endif

class NetworkView {
 public:
  struct Entry {
    uint32_t heard_us;  ///< when the last heartbeat/boot-up arrived
    uint8_t node_id;    ///< 0: free
    uint8_t state;      ///< its NMT state byte (00h boot-up, 04h, 05h, 7Fh)
  };

  /// A received standard data frame (the owner drops RTR and extended
  /// frames: NetworkService::on_can_frame): heartbeats and boot-ups
  /// (701h..77Fh, 1 byte) are recorded, others ignored. A node that does
  /// not find room (the table is full) is counted in overflows().
  void on_frame(const CanFrame& f, uint32_t now_us) {
    if (f.dlc < 1u || f.id < 0x701u || f.id > 0x77Fu) return;
    const uint8_t id = static_cast<uint8_t>(f.id - 0x700u);
    Entry* slot = nullptr;
    for (Entry& e : entries_) {
      if (e.node_id == id) {
        slot = &e;
        break;
      }
      if (slot == nullptr && e.node_id == 0u) slot = &e;
    }
    if (slot == nullptr) {
      if (overflows_ != 0xFFu) ++overflows_;
      return;
    }
    slot->node_id = id;
    slot->state = static_cast<uint8_t>(f.data[0] & 0x7Fu);  // bit 7: guarding toggle
    slot->heard_us = now_us;
  }

  /// The entry of `node_id`, or null when it was never heard.
  const Entry* find(uint8_t node_id) const {
    for (const Entry& e : entries_) {
      if (node_id != 0u && e.node_id == node_id) return &e;
    }
    return nullptr;
  }
  /// Nodes that found no room (never decrements, saturates).
  uint8_t overflows() const { return overflows_; }

 private:
  Entry entries_[kNetViewNodes];
  uint8_t overflows_;
};

}  // namespace gateway
}  // namespace mb2co
