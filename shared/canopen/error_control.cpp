#include "canopen/error_control.h"

#include "canopen/clock.h"

namespace mb2co {
namespace canopen {

void ErrorControl::init(uint8_t node_id) {
  node_id_ = node_id;
  restart_ = true;
  toggle_ = false;
  guarded_ = false;
  life_lost_ = false;
}

static bool send_state(const CanSink& sink, uint8_t node_id, uint8_t byte) {
  CanFrame f = {};
  f.id = 0x700u + node_id;
  f.dlc = 1;
  f.data[0] = byte;
  return sink.send(sink.ctx, f);
}

void ErrorControl::on_guard_request(uint32_t now_us, NmtState state, const CanSink& sink,
                                    uint16_t producer_ms, uint16_t guard_ms,
                                    uint8_t life_factor) {
  if (producer_ms != 0) return;
  send_state(sink, node_id_, static_cast<uint8_t>((toggle_ ? 0x80 : 0x00) | state));
  toggle_ = !toggle_;
  guarded_ = true;
  life_deadline_us_ = now_us + static_cast<uint32_t>(guard_ms) * life_factor * 1000u;
}

ErrorControl::Event ErrorControl::process(uint32_t now_us, NmtState state, const CanSink& sink,
                                          uint16_t producer_ms, uint16_t guard_ms,
                                          uint8_t life_factor) {
  if (restart_) {
    restart_ = false;
    next_heartbeat_us_ = now_us + static_cast<uint32_t>(producer_ms) * 1000u;
    if (guarded_) life_deadline_us_ = now_us + static_cast<uint32_t>(guard_ms) * life_factor * 1000u;
  }
  // A heartbeat the port refused (transmit queue full) is tried again at the
  // next call: consumers must not see a gap that is only ours.
  if (producer_ms != 0 && time_reached(now_us, next_heartbeat_us_) &&
      send_state(sink, node_id_, state)) {
    next_heartbeat_us_ += static_cast<uint32_t>(producer_ms) * 1000u;
    // After a long pause (e.g. the caller was blocked) do not send a burst.
    if (time_reached(now_us, next_heartbeat_us_)) {
      next_heartbeat_us_ = now_us + static_cast<uint32_t>(producer_ms) * 1000u;
    }
  }
  // Life guarding: only once the master has started guarding us.
  const bool guarding = producer_ms == 0 && guard_ms != 0 && life_factor != 0 && guarded_;
  if (guarding && !life_lost_ && time_reached(now_us, life_deadline_us_)) {
    life_lost_ = true;
    return kLifeGuardLost;
  }
  if (life_lost_ && (!guarding || !time_reached(now_us, life_deadline_us_))) {
    life_lost_ = false;
    return kLifeGuardResumed;
  }
  return kNoEvent;
}

}  // namespace canopen
}  // namespace mb2co
