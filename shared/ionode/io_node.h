// The CiA 401-style digital I/O test node used across tests and the demo:
// inputs are written by the owner (hardware pins, a test, the simulator) and
// published by TPDO1; outputs arrive by RPDO1 or SDO. Its own node id and
// CAN bit rate are 2001h/1-2, kept like the gateway's 2000h/1-2: saved with
// 1010h (the node's two-slot storage, canopen/param_storage.h), a written
// id in force from the next reset communication, the bit rate from the next
// reset; a reset node without a saved set goes back to the power-on id.
// CiA 401 inputs: 6000h is the pins' levels with the polarity 6002h applied
// (a 1 inverts the bit), at every set_input() and write of 6002h (a written
// polarity shows at once); a change of 6000h sends the TPDOs that map 6000h
// (with transmission type 255, the device profile's event) only when 6005h
// is TRUE and a changed bit is in the any-change mask 6006h, or rose and is
// in 6007h, or fell and is in 6008h. Type 254 sends on any change.
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

  /// Power-on: boot-up with the saved node id 2001h/1 when a saved set is
  /// found (before the boot-up: the node never announces itself under
  /// another id), else with `default_node_id` (1..127). Set the storage
  /// (node().set_storage) and the CAN control before.
  void start(uint8_t default_node_id, uint32_t now_us);
  void receive(const CanFrame& f, uint32_t now_us) { node_.receive(f, now_us); }
  /// The I/O node as a CAN port's device (platform/device_port.h): frames
  /// and the controller's events to its node.
  CanInput can_input() { return CanInput{&IoNode::receive_of, &IoNode::controller_state_of, this}; }
  /// Its acceptance ranges are the node's (a port's choice of filters).
  static constexpr uint16_t kWidestRange = canopen::Node::kWidestRange;
  void process(uint32_t now_us) { node_.process(now_us); }

  /// Input byte `n` (0 or 1) as read from the pins (before the polarity);
  /// published as the interrupt masks say.
  void set_input(uint8_t n, uint8_t value);
  /// Output byte `n` (0 or 1) as last written by the network.
  uint8_t output(uint8_t n) const;

  canopen::Node& node() { return node_; }
  canopen::ObjectDictionary& od() { return od_; }

 private:
  friend struct IoNodeHandlers;  // the OD's handlers of 6002h and 6200h (io_node_od.h)
  static void on_reset(void* ctx, canopen::NmtReset kind);
  /// 6000h/n+1 from the pins and `polarity`; a change the masks let
  /// through requests the TPDOs mapping 6000h.
  void update_input(uint8_t n, uint8_t polarity);
  void request_input_pdos();
  static void receive_of(void* ctx, const CanFrame& f, uint32_t now_us) {
    static_cast<IoNode*>(ctx)->node_.receive(f, now_us);
  }
  static void controller_state_of(void* ctx, uint8_t events, bool passive, uint32_t now_us) {
    static_cast<IoNode*>(ctx)->node_.on_controller_state(events, passive, now_us);
  }

  od::IoNodeValues values_;
  canopen::ObjectDictionary od_;
  canopen::Node node_;
  uint32_t device_type_;
  uint16_t row_inputs_;
  uint16_t row_outputs_;
  uint16_t row_local_;
  uint16_t row_polarity_;  ///< 6002h/1; 6005h/0 to 6008h/1 follow it, 3 rows apart
  uint8_t pins_[2];        ///< set_input()'s levels, before the polarity
};

}  // namespace ionode
}  // namespace mb2co
