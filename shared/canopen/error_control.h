// Error control of the node itself (CiA 301 §7.2.8.3): the heartbeat producer
// (1017h) and, when no heartbeat is produced, node guarding answers with life
// guarding (100Ch guard time × 100Dh life time factor, at most 35.8 min).
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "canopen/nmt_slave.h"

namespace mb2co {
namespace canopen {

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class ErrorControl {
 public:
  enum Event : uint8_t { kNoEvent = 0, kLifeGuardLost, kLifeGuardResumed };

  void init(uint8_t node_id);
  /// 1017h, 100Ch or 100Dh was written: timers restart at the next process().
  void restart() { restart_ = true; }
  /// Node guarding request (RTR on 700h+id). Answered only while the node
  /// produces no heartbeat (one error-control protocol at a time).
  void on_guard_request(uint32_t now_us, NmtState state, const CanSink& sink, uint16_t producer_ms,
                        uint16_t guard_ms, uint8_t life_factor);
  /// Sends due heartbeats; returns a life-guarding event when one happened.
  Event process(uint32_t now_us, NmtState state, const CanSink& sink, uint16_t producer_ms, uint16_t guard_ms,
                uint8_t life_factor);
  /// Lowers `d` to when process() with the same settings must run next
  /// (Node::next_deadline): a restart, the next heartbeat (also one the port
  /// refused: now), the life guarding deadline, a pending life event.
  void next_deadline(NextDeadline& d, uint16_t producer_ms, uint16_t guard_ms, uint8_t life_factor) const;

 private:
  uint32_t next_heartbeat_us_;
  uint32_t life_deadline_us_;
  uint8_t node_id_;
  bool restart_;  ///< set by init() (every reset) before the first process()
  bool toggle_;
  bool guarded_;    ///< a guarding request arrived since (re)start
  bool life_lost_;  ///< life guarding event raised, not yet resumed
};

}  // namespace canopen
}  // namespace mb2co
