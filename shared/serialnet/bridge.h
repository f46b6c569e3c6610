// The smart bridge of seed 003 §3.2.8 between one serial CANopen segment and
// an 11-bit CAN bus: it looks at an identifier's function code and node id,
// forwards only what the other side consumes, and translates the node id by
// an offset (the function code by the connection set's table, connection_set.h).
// The CAN side sees the serial nodes 1..n as ordinary CANopen nodes
// offset+1..offset+n (boot-up, heartbeat, EMCY, TPDOs, SDO responses); the
// serial nodes get from CAN what is addressed to them.
//
// Routes (by CAN function code; "node" is the node-id field):
//   serial → CAN: heartbeat/boot-up 700h, EMCY 080h+n, TPDO1 180h, TPDO2 280h,
//                 SDO response 580h                        (node id + offset)
//   CAN → serial: NMT 000h (its target byte data[1] less the offset; 0 stays
//                 0: all nodes), RPDO1 200h, RPDO2 300h, SDO request 600h of
//                 a serial node (node id - offset), and the CAN ids listed in
//                 BridgeConfig::extra_to_serial (what a serial node's RPDO was
//                 set to consume, e.g. a CAN node's TPDO1 in the offset range)
//   never:        SYNC 080h either way (on the segment a SYNC is a poll that
//                 opens a window: a CAN SYNC there would steal windows; the
//                 segment's polls mean nothing on CAN), TIME, the bridge's own
//                 window id, anything of a node outside the segment.
// What the connection set has no code for (TPDO3, RTR, extended) is dropped
// and counted: the serial side could not carry it.
//
// The bridge is the segment's bus master: its SerialLink is the poller
// (Access::kPoller) or the token starter (kTokenStarter), with a window of
// its own (bridge_node, inside first..last of the segment) in which the
// CAN→serial traffic goes out. Frames the link or the CAN port refuse (their
// queues are full) wait in the bridge's own queue (8 each way) and are
// retried in order by process(); beyond that they are dropped and counted.
//
// Contract: hand in every CAN frame (on_can, or through can_input() from a
// CAN port) and every line byte (on_byte, never the bridge's own echo);
// call process() at next_deadline(). One context; no heap.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "platform/device_port.h"
#include "serialnet/serial_link.h"

namespace mb2co {
namespace serialnet {

struct BridgeConfig {
  /// The segment (same on every device of it); access kPoller or
  /// kTokenStarter, first..last includes bridge_node.
  BusConfig bus;
  uint8_t bridge_node;  ///< the bridge's window on the segment (not forwarded)
  uint8_t node_offset;  ///< CAN node id = serial node id + node_offset (<= 127)
  /// Optional CAN ids serial nodes consume besides the default routes
  /// (caller-owned, constant, outliving the bridge); null when none.
  const uint16_t* extra_to_serial;
  uint8_t extra_count;
};

/// Why a BridgeConfig cannot work (kOk: it can).
enum class BridgeConfigError : uint8_t {
  kOk,
  kBus,         ///< check_config() refuses the segment
  kAccess,      ///< the bridge must be the poller or the token starter
  kBridgeNode,  ///< bridge_node outside first..last
  kOffset,      ///< last node + offset beyond 127
};
BridgeConfigError check_bridge_config(const BridgeConfig& config);

/// Serial node of `config`'s segment that CAN node `can_node` stands for
/// (first..last less the offset, never the bridge's own window); false: none.
bool serial_node_of(const BridgeConfig& config, uint16_t can_node, uint8_t* serial_node);
/// Seed 003's figure 7 puts several segments on one CAN bus, one bridge
/// each: true when two of them would give serial nodes the same CAN node id
/// (a heartbeat, a TPDO, an SDO channel claimed twice). Whoever configures
/// the bridges of one CAN bus refuses such a pair.
bool bridges_clash(const BridgeConfig& a, const BridgeConfig& b);

/// A bounded FIFO of frames waiting for a full queue to accept them.
class FrameFifo {
 public:
  static const uint8_t kCapacity = 8;
  bool push(const CanFrame& f);
  bool empty() const { return count_ == 0; }
  uint8_t size() const { return count_; }
  const CanFrame& front() const { return frames_[head_]; }
  void pop();

 private:
  CanFrame frames_[kCapacity];
  uint8_t head_ = 0;
  uint8_t count_ = 0;
};

class Bridge {
 public:
  /// `line`: the segment (one whole message per write); `can`: the CAN bus.
  /// `config` must pass check_bridge_config().
  Bridge(const BridgeConfig& config, const modbus::ByteSink& line, const CanSink& can);

  /// A frame from the CAN bus.
  void on_can(const CanFrame& f, uint32_t now_us);
  /// The bridge as a CAN port's device (platform/device_port.h): every frame
  /// to on_can; it takes no controller events. It sets no filters: a port
  /// keeps them open (every frame the routes above may forward).
  CanInput can_input() { return CanInput{&Bridge::from_can, nullptr, this}; }
  /// A byte from the segment, `byte_us` when it was complete.
  void on_byte(uint8_t byte, uint32_t byte_us) { link_.on_byte(byte, byte_us); }
  /// Retries what waits, runs the segment's bus access.
  void process(uint32_t now_us);
  void next_deadline(NextDeadline& d) const;

  /// Counters that never decrement (saturate at 0xFFFF).
  struct Counters {
    uint16_t to_can;        ///< frames handed to the CAN side
    uint16_t to_serial;     ///< frames handed to the segment's link
    uint16_t polls;         ///< the segment's SYNCs (polls, token passes, the bridge's own): not forwarded
    uint16_t can_syncs;     ///< CAN SYNCs held back from the segment
    uint16_t not_consumed;  ///< no route: the other side does not consume it
    uint16_t unmappable;    ///< no serial form (code missing in the set, RTR, extended)
    uint16_t overflow;      ///< dropped: the bridge's own queue was full too
  };
  const Counters& counters() const { return counters_; }
  const SerialLink& link() const { return link_; }
  /// Frames waiting for the segment / for the CAN port.
  uint8_t waiting_to_serial() const { return to_serial_.size(); }
  uint8_t waiting_to_can() const { return to_can_.size(); }

  /// The frame `in` of a serial node (ids as the link delivers them: node
  /// ids of the segment) as it goes onto CAN; false: not forwarded (counted).
  bool route_to_can(const CanFrame& in, CanFrame* out);
  /// The frame `in` from CAN as the link takes it; false: not forwarded (counted).
  bool route_to_serial(const CanFrame& in, CanFrame* out);

 private:
  static void receive(void* ctx, const CanFrame& f, uint32_t now_us);
  static void from_can(void* ctx, const CanFrame& f, uint32_t now_us) {
    static_cast<Bridge*>(ctx)->on_can(f, now_us);
  }
  void from_serial(const CanFrame& f);
  /// Sends what waits, in order, until a queue refuses.
  void flush();
  bool extra_to_serial(uint16_t can_id) const;
  static void bump(uint16_t& c) {
    if (c != 0xFFFFu) ++c;
  }

  BridgeConfig config_;
  CanSink can_;
  SerialLink link_;
  FrameFifo to_serial_;
  FrameFifo to_can_;
  Counters counters_ = {};
};

}  // namespace serialnet
}  // namespace mb2co
