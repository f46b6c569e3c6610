// What `serve` tells its clients of the network on its own: the NMT state
// each node reports (boot-up, heartbeats, lost when they stop for the
// consumer time) and each EMCY, as the lines canopend logs for them
// (CANopenLinux's CO_error_msgs.h):
//
//   CANopen Remote node ID = 0x03 (index = 2): NMT state changed to: "operational" (5)
//   CANopen Emergency message from node 0x03: errorCode=0x8210, errorRegister=0x11, errorBit=0x00,
//   infoCode=0x00000000
//
// States as CANopenNode numbers them: "initializing" (0, a boot-up),
// "pre-operational" (127), "operational" (5), "stopped" (4), "unknown" (-1,
// heartbeats lost). "index" is the node's slot in the consumer table: every
// node id 1..127 is watched, node N in slot N-1. errorBit is the EMCY's byte
// 3, infoCode its bytes 4..7 (little-endian), as CANopenNode splits the
// manufacturer-specific field. SocketCAN only: a gateway passes no frames.
#pragma once
#include <stdint.h>

#include <functional>
#include <string>

#include "bus_loop.h"
#include "canopen/master/emcy_consumer.h"
#include "canopen/master/node_monitor.h"

namespace mb2co {
namespace master {

/// canopend's line for a node's NMT state (a state byte, or -1: lost).
std::string nmt_state_line(uint8_t node, int state);
/// canopend's line for an EMCY.
std::string emcy_line(uint8_t node, const canopen::EmcyMessage& m);

class NetworkEvents final : public BusService {
 public:
  using Listener = std::function<void(const std::string& line)>;
  /// Watches the heartbeats of nodes 1..127 with `consumer_ms` (>= 2).
  NetworkEvents(uint16_t consumer_ms, Listener listener);

  void on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink) override;
  void process(uint32_t now_us, const CanSink& sink) override { monitors_.process(now_us, sink); }
  void next_deadline(NextDeadline& d) const override { monitors_.next_deadline(d); }

 private:
  static void on_monitor(void* ctx, uint8_t node, canopen::MonitorEvent e, uint8_t from, uint8_t to);
  static void on_emcy(void* ctx, uint8_t node, const canopen::EmcyMessage& m, uint32_t now_us);

  Listener listener_;
  canopen::NodeMonitorTable<127> monitors_;
  canopen::EmcyConsumer<127> emcy_;
  int reported_[128];  ///< the state last told per node (-2: none yet)
};

}  // namespace master
}  // namespace mb2co
