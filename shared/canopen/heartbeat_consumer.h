// Heartbeat consumer (CiA 301 §7.2.8.3.2, object 1016h): watches up to
// kHbConsumers remote nodes. Each 1016h sub-entry holds node id (bits 16–23)
// and consumer time in ms (bits 0–15); time 0 or node id 0 disables it.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/od_comm.h"

namespace mb2co {
namespace canopen {

enum HbEvent : uint8_t {
  kHbStarted = 1,       ///< first heartbeat after configuration, boot-up or loss
  kHbLost = 2,          ///< consumer time elapsed without a heartbeat
  kHbStateChanged = 3,  ///< the remote node reported another NMT state
  kHbBootUp = 4,        ///< the remote node sent its boot-up message (it was reset)
};

enum HbRemoteState : uint8_t {
  kHbUnconfigured = 0,
  kHbUnknown,  ///< configured, nothing heard yet (or heard a boot-up)
  kHbActive,   ///< heartbeats arrive in time
  kHbTimeout,  ///< lost: show as unknown, never as running
};

/// Called for every event; `nmt_state` is the remote's last reported state.
typedef void (*HbEventCallback)(void* ctx, uint8_t node_id, HbEvent event, uint8_t nmt_state);

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class HeartbeatConsumer {
 public:
  /// Re-reads one 1016h sub-entry (1-based `sub`); the monitor starts over.
  /// Out of line: Node::reset() and the 1016h write hook would each carry a copy.
  __attribute__((noinline)) void configure(uint8_t sub, uint32_t entry);
  void set_callback(HbEventCallback cb, void* ctx) {
    cb_ = cb;
    cb_ctx_ = ctx;
  }
  /// Heartbeat or boot-up on 700h+id (1 data byte). Returns true if consumed.
  bool on_frame(const CanFrame& f, uint32_t now_us);
  /// Detects timeouts; returns how many consumers are in kHbTimeout.
  uint8_t process(uint32_t now_us);
  /// Lowers `d` to the earliest consumer time running out.
  void next_deadline(NextDeadline& d) const;
  /// All monitors back to "unknown" (NMT stopped, reset communication).
  void reset_all();

  HbRemoteState remote_state(uint8_t node_id) const;
  uint8_t remote_nmt(uint8_t node_id) const;

 private:
  struct Monitor {
    uint32_t deadline_us;
    uint16_t time_ms;
    uint8_t node_id;
    uint8_t state;  ///< HbRemoteState
    uint8_t nmt;    ///< last NMT state byte heard
  };
  void emit(const Monitor& m, HbEvent e) {
    if (cb_ != nullptr) cb_(cb_ctx_, m.node_id, e, m.nmt);
  }
  Monitor mon_[kHbConsumers];
  HbEventCallback cb_;
  void* cb_ctx_;
};

}  // namespace canopen
}  // namespace mb2co
