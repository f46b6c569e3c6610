// The master's EMCY consumer (CiA 301 §7.2.7): the emergency messages of all
// nodes on their default COB-IDs 081h..0FFh (080h + node id), decoded, the
// last one and a count kept per node. What the codes and register bits mean:
// emcy_names.h.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace canopen {

/// One decoded emergency message.
struct EmcyMessage {
  uint16_t code;            ///< emergency error code (0000h: error reset)
  uint8_t error_register;   ///< the node's 1001h (ErrorRegisterBit bits)
  uint8_t manufacturer[5];  ///< manufacturer-specific error field, bytes 3..7
};

/// Decodes `f` if it is an EMCY of a node: a standard data frame on
/// 081h..0FFh with 8 data bytes (CiA 301: always 8). *node_id = id - 080h.
bool emcy_decode(const CanFrame& f, uint8_t* node_id, EmcyMessage* out);

/// Told of every EMCY received (after it is recorded).
struct EmcyListener {
  void (*on_emcy)(void* ctx, uint8_t node_id, const EmcyMessage& emcy, uint32_t now_us);
  void* ctx;
};

/// The last EMCY of one node and how many came.
struct EmcyRecord {
  EmcyMessage last;
  uint32_t last_us;  ///< when `last` was received
  uint16_t count;    ///< EMCYs received (error resets included; saturates)
  uint8_t node_id;   ///< 0: slot free
};

/// Records the EMCYs of up to `Capacity` nodes (1..127); a node gets a slot
/// at its first EMCY. EMCYs of further nodes are still decoded and told to
/// the listener, and counted in unrecorded().
template <uint8_t Capacity>
class EmcyConsumer {
  static_assert(Capacity >= 1 && Capacity <= 127, "1..127 nodes");

 public:
  void set_listener(const EmcyListener& listener) { listener_ = listener; }
  /// True if `f` is an EMCY (consumed). Frames on 081h..0FFh that are not 8
  /// bytes long (or are RTR) are counted in malformed() and not consumed.
  bool on_frame(const CanFrame& f, uint32_t now_us) {
    uint8_t node_id = 0;
    EmcyMessage m;
    if (!emcy_decode(f, &node_id, &m)) {
      if (!f.extended() && f.id > 0x080u && f.id <= 0x0FFu) saturating_inc(&malformed_);
      return false;
    }
    EmcyRecord* r = slot(node_id);
    if (r != nullptr) {
      r->node_id = node_id;
      r->last = m;
      r->last_us = now_us;
      saturating_inc(&r->count);
    } else {
      saturating_inc(&unrecorded_);
    }
    if (listener_.on_emcy != nullptr) listener_.on_emcy(listener_.ctx, node_id, m, now_us);
    return true;
  }
  /// The record of `node_id`, nullptr when none came from it.
  const EmcyRecord* record(uint8_t node_id) const {
    for (const EmcyRecord& r : rec_) {
      if (r.node_id == node_id && node_id != 0) return &r;
    }
    return nullptr;
  }
  uint16_t count(uint8_t node_id) const {
    const EmcyRecord* r = record(node_id);
    return r != nullptr ? r->count : 0;
  }
  /// Forgets every record (counts too).
  void clear() {
    for (EmcyRecord& r : rec_) r = EmcyRecord();
  }
  uint16_t malformed() const { return malformed_; }
  uint16_t unrecorded() const { return unrecorded_; }

 private:
  static void saturating_inc(uint16_t* n) {
    if (*n != 0xFFFF) ++*n;
  }
  EmcyRecord* slot(uint8_t node_id) {
    EmcyRecord* free_slot = nullptr;
    for (EmcyRecord& r : rec_) {
      if (r.node_id == node_id) return &r;
      if (free_slot == nullptr && r.node_id == 0) free_slot = &r;
    }
    return free_slot;
  }

  EmcyRecord rec_[Capacity] = {};
  EmcyListener listener_ = {nullptr, nullptr};
  uint16_t malformed_ = 0;
  uint16_t unrecorded_ = 0;
};

}  // namespace canopen
}  // namespace mb2co
