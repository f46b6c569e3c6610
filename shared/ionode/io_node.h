// The CiA 401-style digital I/O test node used across tests and the demo:
// inputs are written by the owner (hardware pins, a test, the simulator) and
// published by TPDO1; outputs arrive by RPDO1 or SDO.
#pragma once
#include <stdint.h>

#include "canopen/node.h"
#include "ionode/io_node_od.h"

namespace mb2co {
namespace ionode {

class IoNode {
 public:
  /// `device_type` is what 1000h reports (default 00030191h: CiA 401, in+out).
  IoNode(const CanSink& sink, uint32_t device_type = 0x00030191u);

  void start(uint8_t node_id, uint32_t now_us) { node_.start(node_id, now_us); }
  void receive(const CanFrame& f, uint32_t now_us) { node_.receive(f, now_us); }
  void process(uint32_t now_us) { node_.process(now_us); }

  /// Input byte `n` (0 or 1) as read from the pins; published on change.
  void set_input(uint8_t n, uint8_t value);
  /// Output byte `n` (0 or 1) as last written by the network.
  uint8_t output(uint8_t n) const;

  canopen::Node& node() { return node_; }
  canopen::ObjectDictionary& od() { return od_; }

 private:
  static canopen::HookResult app_write(void* ctx, uint8_t hook, uint16_t index, uint8_t sub,
                                       const uint8_t* data, uint16_t len, bool apply);
  static void on_reset(void* ctx, canopen::NmtReset kind);

  od::IoNodeValues values_;
  canopen::ObjectDictionary od_;
  canopen::Node node_;
  uint32_t device_type_;
  uint16_t row_inputs_;
  uint16_t row_outputs_;
  uint16_t row_local_;
};

}  // namespace ionode
}  // namespace mb2co
