#include "serve_events.h"

#include <stdio.h>

#include "canopen/nmt_slave.h"

namespace mb2co {
namespace master {

namespace {

const char* state_name(int state) {
  switch (state) {
    case canopen::kNmtInitialising:
      return "initializing";
    case canopen::kNmtPreOperational:
      return "pre-operational";
    case canopen::kNmtOperational:
      return "operational";
    case canopen::kNmtStopped:
      return "stopped";
    default:
      return "unknown";
  }
}

}  // namespace

std::string nmt_state_line(uint8_t node, int state) {
  char line[128];
  snprintf(line, sizeof line,
           "CANopen Remote node ID = 0x%02X (index = %d): NMT state changed to: \"%s\" (%d)", node, node - 1,
           state_name(state), state);
  return line;
}

std::string emcy_line(uint8_t node, const canopen::EmcyMessage& m) {
  const uint32_t info =
      static_cast<uint32_t>(m.manufacturer[1]) | static_cast<uint32_t>(m.manufacturer[2]) << 8 |
      static_cast<uint32_t>(m.manufacturer[3]) << 16 | static_cast<uint32_t>(m.manufacturer[4]) << 24;
  char line[160];
  snprintf(
      line, sizeof line,
      "CANopen Emergency message from node 0x%02X: errorCode=0x%04X, errorRegister=0x%02X, errorBit=0x%02X, "
      "infoCode=0x%08X",
      node, m.code, m.error_register, m.manufacturer[0], info);
  return line;
}

NetworkEvents::NetworkEvents(uint16_t consumer_ms, Listener listener) : listener_(std::move(listener)) {
  for (int& r : reported_) r = -2;
  monitors_.set_listener(canopen::MonitorListener{&NetworkEvents::on_monitor, this});
  emcy_.set_listener(canopen::EmcyListener{&NetworkEvents::on_emcy, this});
  // The nodes' producer times are theirs: any below the consumer time.
  for (uint8_t id = 1; id <= 127; ++id) monitors_.monitor(id)->watch_heartbeat(id, 1, consumer_ms);
}

void NetworkEvents::on_frame(const CanFrame& f, uint32_t now_us, const CanSink&) {
  if (monitors_.on_frame(f, now_us)) return;
  emcy_.on_frame(f, now_us);
}

void NetworkEvents::on_monitor(void* ctx, uint8_t node, canopen::MonitorEvent e, uint8_t, uint8_t to) {
  auto* self = static_cast<NetworkEvents*>(ctx);
  if (e == canopen::kMonitorToggleError) return;  // guarding only: serve watches heartbeats
  // A boot-up is told every time (the node was reset); otherwise a line
  // when the state told changes: back with the state it had says it again.
  const int state = e == canopen::kMonitorNodeLost ? -1 : e == canopen::kMonitorBootUp ? 0 : to;
  if (e != canopen::kMonitorBootUp && self->reported_[node] == state) return;
  self->reported_[node] = state;
  self->listener_(nmt_state_line(node, state));
}

void NetworkEvents::on_emcy(void* ctx, uint8_t node, const canopen::EmcyMessage& m, uint32_t) {
  static_cast<NetworkEvents*>(ctx)->listener_(emcy_line(node, m));
}

}  // namespace master
}  // namespace mb2co
