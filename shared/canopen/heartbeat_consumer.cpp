#include "canopen/heartbeat_consumer.h"

#include "canopen/clock.h"

namespace mb2co {
namespace canopen {

void HeartbeatConsumer::configure(uint8_t sub, uint32_t entry) {
  if (sub == 0 || sub > kHbConsumers) return;
  Monitor& m = mon_[sub - 1];
  m.node_id = static_cast<uint8_t>(entry >> 16);
  m.time_ms = static_cast<uint16_t>(entry);
  m.nmt = 0;
  m.state = (m.node_id != 0 && m.node_id <= 127 && m.time_ms != 0) ? kHbUnknown : kHbUnconfigured;
}

bool HeartbeatConsumer::on_frame(const CanFrame& f, uint32_t now_us) {
  if (f.rtr() || f.dlc != 1) return false;
  const uint8_t id = static_cast<uint8_t>(f.id - 0x700u);
  bool consumed = false;
  for (Monitor& m : mon_) {
    if (m.state == kHbUnconfigured || m.node_id != id) continue;
    consumed = true;
    const uint8_t nmt = f.data[0] & 0x7F;
    if (nmt == 0) {  // boot-up: the node was reset; its state is unknown again
      m.nmt = 0;
      m.state = kHbUnknown;
      emit(m, kHbBootUp);
      continue;
    }
    const bool was_active = m.state == kHbActive;
    const bool changed = m.nmt != nmt;
    m.nmt = nmt;
    m.state = kHbActive;
    m.deadline_us = now_us + static_cast<uint32_t>(m.time_ms) * 1000u;
    if (!was_active) {
      emit(m, kHbStarted);
    } else if (changed) {
      emit(m, kHbStateChanged);
    }
  }
  return consumed;
}

uint8_t HeartbeatConsumer::process(uint32_t now_us) {
  uint8_t lost = 0;
  for (Monitor& m : mon_) {
    if (m.state == kHbActive && time_reached(now_us, m.deadline_us)) {
      m.state = kHbTimeout;
      emit(m, kHbLost);
    }
    if (m.state == kHbTimeout) ++lost;
  }
  return lost;
}

void HeartbeatConsumer::next_deadline(NextDeadline& d) const {
  for (const Monitor& m : mon_) {
    if (m.state == kHbActive) d.at(m.deadline_us);
  }
}

void HeartbeatConsumer::reset_all() {
  for (Monitor& m : mon_) {
    if (m.state != kHbUnconfigured) m.state = kHbUnknown;
    m.nmt = 0;
  }
}

HbRemoteState HeartbeatConsumer::remote_state(uint8_t node_id) const {
  for (const Monitor& m : mon_) {
    if (m.state != kHbUnconfigured && m.node_id == node_id) return static_cast<HbRemoteState>(m.state);
  }
  return kHbUnconfigured;
}

uint8_t HeartbeatConsumer::remote_nmt(uint8_t node_id) const {
  for (const Monitor& m : mon_) {
    if (m.state != kHbUnconfigured && m.node_id == node_id) return m.nmt;
  }
  return 0;
}

}  // namespace canopen
}  // namespace mb2co
