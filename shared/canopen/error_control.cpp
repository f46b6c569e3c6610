#include "canopen/error_control.h"

#include "canopen/clock.h"
#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

void ErrorControl::init(uint8_t node_id) {
  node_id_ = node_id;
  restart_ = true;
  toggle_ = false;
  guarded_ = false;
  life_lost_ = false;
}

// Life time of node guarding: guard time x life time factor, at most
// kMaxLifeMs. 100Ch x 100Dh reaches 65535 x 255 ms: in us that overflows 32
// bits, and a deadline 2^31 us or more ahead reads as passed to time_reached()
// (life guarding then failed at the first guard request). Out of line: two
// callers.
static const uint32_t kMaxLifeMs = 0x7FFFFFFFu / 1000u;  // 35.8 min
__attribute__((noinline)) static uint32_t life_time_us(uint16_t guard_ms, uint8_t life_factor) {
  const uint32_t ms = static_cast<uint32_t>(guard_ms) * life_factor;
  return (ms < kMaxLifeMs ? ms : kMaxLifeMs) * 1000u;
}

static bool send_state(const CanSink& sink, uint8_t node_id, uint8_t byte) {
  return send_frame(sink, static_cast<uint16_t>(0x700u + node_id), 1, &byte);
}

void ErrorControl::on_guard_request(uint32_t now_us, NmtState state, const CanSink& sink,
                                    uint16_t producer_ms, uint16_t guard_ms, uint8_t life_factor) {
  if (producer_ms != 0) return;
  send_state(sink, node_id_, static_cast<uint8_t>((toggle_ ? 0x80 : 0x00) | state));
  toggle_ = !toggle_;
  guarded_ = true;
  life_deadline_us_ = now_us + life_time_us(guard_ms, life_factor);
}

ErrorControl::Event ErrorControl::process(uint32_t now_us, NmtState state, const CanSink& sink,
                                          uint16_t producer_ms, uint16_t guard_ms, uint8_t life_factor) {
  const uint32_t period_us = static_cast<uint32_t>(producer_ms) * 1000u;
  if (restart_) {
    restart_ = false;
    next_heartbeat_us_ = now_us + period_us;
    if (guarded_) life_deadline_us_ = now_us + life_time_us(guard_ms, life_factor);
  }
  // A heartbeat the port refused (transmit queue full) is tried again at the
  // next call: consumers must not see a gap that is only ours.
  if (producer_ms != 0 && time_reached(now_us, next_heartbeat_us_) && send_state(sink, node_id_, state)) {
    next_heartbeat_us_ += period_us;
    // After a long pause (e.g. the caller was blocked) do not send a burst.
    if (time_reached(now_us, next_heartbeat_us_)) next_heartbeat_us_ = now_us + period_us;
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

void ErrorControl::next_deadline(NextDeadline& d, uint16_t producer_ms, uint16_t guard_ms,
                                 uint8_t life_factor) const {
  if (restart_) return d.now();
  if (producer_ms != 0) d.at(next_heartbeat_us_);
  const bool guarding = producer_ms == 0 && guard_ms != 0 && life_factor != 0 && guarded_;
  if (!life_lost_) {
    if (guarding) d.at(life_deadline_us_);
    return;
  }
  if (!guarding || !time_reached(d.now_us(), life_deadline_us_)) return d.now();  // resumed
  // Lost until a guard request; process() also reports "resumed" once the
  // deadline lies 2^31 us behind (time_reached() wraps): that is a deadline too.
  d.at(life_deadline_us_ + 0x80000000u);
}

}  // namespace canopen
}  // namespace mb2co
