#include "canopen/master/node_monitor.h"

namespace mb2co {
namespace canopen {

// guard time × life time factor reaches 65535 × 255 ms, which overflows 32
// bits in µs, and a deadline 2^31 µs or more ahead reads as passed to
// time_reached(): capped as the node's life guarding caps it (35.8 min).
static const uint32_t kMaxLifeMs = 0x7FFFFFFFu / 1000u;

bool NodeMonitor::start(uint8_t node_id, uint16_t time_ms, bool guarding) {
  if (node_id == 0 || node_id > 127 || time_ms == 0) return false;
  *this = NodeMonitor();
  node_id_ = node_id;
  link_ = kLinkWaiting;
  guarding_ = guarding;
  rtr_due_ = guarding;
  return true;
}

bool NodeMonitor::watch_heartbeat(uint8_t node_id, uint16_t producer_ms, uint16_t consumer_ms) {
  if (producer_ms == 0 || consumer_ms <= producer_ms) return false;
  if (!start(node_id, consumer_ms, false)) return false;
  producer_ms_ = producer_ms;
  life_us_ = static_cast<uint32_t>(consumer_ms) * 1000u;
  return true;
}

bool NodeMonitor::watch_guarding(uint8_t node_id, uint16_t guard_ms, uint8_t life_factor) {
  if (life_factor == 0 || !start(node_id, guard_ms, true)) return false;
  guard_ms_ = guard_ms;
  const uint32_t life_ms = static_cast<uint32_t>(guard_ms) * life_factor;
  life_us_ = (life_ms < kMaxLifeMs ? life_ms : kMaxLifeMs) * 1000u;
  return true;
}

void NodeMonitor::heard(uint8_t state, uint32_t now_us, const MonitorListener& l) {
  const uint8_t old = state_;
  const bool was_lost = link_ == kLinkLost;
  link_ = kLinkAlive;
  deadline_us_ = now_us + life_us_;
  state_ = state;
  if (was_lost) emit(l, kMonitorNodeBack, state_);
  if (old != state) emit(l, kMonitorStateChanged, old);
}

bool NodeMonitor::on_frame(const CanFrame& f, uint32_t now_us, const MonitorListener& l) {
  if (link_ == kLinkOff || f.rtr() || f.extended() || f.id != 0x700u + node_id_ || f.dlc != 1) return false;
  const uint8_t byte = f.data[0];
  if (byte == 0x00) {  // boot-up: the node was reset; it is heard, but not armed
    const uint8_t old = state_;
    const bool was_lost = link_ == kLinkLost;
    link_ = kLinkWaiting;
    state_ = 0x00;
    toggle_ = false;  // a reset node starts its guarding answers with toggle 0
    if (was_lost) emit(l, kMonitorNodeBack, state_);
    emit(l, kMonitorBootUp, old);
    return true;
  }
  if (guarding_) {
    const bool toggle = (byte & 0x80) != 0;
    // After a loss the node may have been reset unseen: resynchronise.
    if (toggle != toggle_ && link_ != kLinkLost) {
      if (toggle_errors_ != 0xFF) ++toggle_errors_;
      toggle_ = !toggle;  // the next answer should alternate from this one
      emit(l, kMonitorToggleError, state_);
      return true;  // not a valid answer: the life time keeps running
    }
    toggle_ = !toggle;
  }
  heard(static_cast<uint8_t>(byte & 0x7F), now_us, l);
  return true;
}

void NodeMonitor::process(uint32_t now_us, const CanSink& sink, const MonitorListener& l) {
  if (link_ == kLinkOff) return;
  if (guarding_ && (rtr_due_ || time_reached(now_us, next_rtr_us_))) {
    CanFrame rtr = {};
    rtr.id = 0x700u + node_id_;
    rtr.dlc = 1;
    rtr.flags = CanFrame::kRtr;
    if (sink.send(sink.ctx, rtr)) {
      const uint32_t period_us = static_cast<uint32_t>(guard_ms_) * 1000u;
      next_rtr_us_ = rtr_due_ ? now_us + period_us : next_rtr_us_ + period_us;
      // After a long pause (the caller was blocked) no burst of RTRs.
      if (time_reached(now_us, next_rtr_us_)) next_rtr_us_ = now_us + period_us;
      rtr_due_ = false;
    } else if (send_failures_ != 0xFF) {
      ++send_failures_;
    }
  }
  if (link_ == kLinkAlive && time_reached(now_us, deadline_us_)) {
    link_ = kLinkLost;
    emit(l, kMonitorNodeLost, state_);
  }
}

void NodeMonitor::next_deadline(NextDeadline& d) const {
  if (link_ == kLinkOff) return;
  if (guarding_) {
    if (rtr_due_) {
      d.now();
    } else {
      d.at(next_rtr_us_);
    }
  }
  if (link_ == kLinkAlive) d.at(deadline_us_);
}

}  // namespace canopen
}  // namespace mb2co
