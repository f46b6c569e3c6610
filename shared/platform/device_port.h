// The whole contract between the portable core of a device (gateway::Gateway,
// ionode::IoNode, serialnet::Bridge; canopen::Node inside the first two) and
// the platform it runs on: the AVR ports (MCP2515, UART, EEPROM), the Linux
// ports (SocketCAN, tty/pty, file) and the line simulator. In the shape of
// libcanard's canard_vtable_t and CANopenNode's CO_driver.h: plain function
// pointers with a context, no virtual functions, nothing owned by the core.
//
// What a port hands the device, and how:
//
//   a CAN frame   CanInput::receive    every frame the controller received,
//                                      whatever its id: the device routes it
//                                      (node core, FC 2Bh/0Dh's network
//                                      service, the bridge's segment)
//   controller    CanInput::controller_state
//                                      events of the CAN controller (overrun,
//                                      error passive, bus-off recovered); the
//                                      device's node decides the EMCY
//   serial in     SlaveCore::on_char / Gateway::on_serial_byte, Bridge::on_byte
//
// What the core asks of a port, and when:
//
//   send frame    CanSink::send        from Node::start/receive/process
//   serial out    ByteSink::write      from SlaveCore::process or on_char (one
//                                      ADU per call, when a request is complete)
//   storage       ParamStorage         from Node::start and reset (load),
//                                      from an SDO/Modbus write of 1011h, and
//                                      from Node::process while a save of
//                                      1010h runs (one byte per write, when
//                                      ParamStorage::ready says so)
//   set bit rate  CanControl::set_bitrate
//                                      from Gateway::on_reset only: at power-on
//                                      (Gateway::start) and at every reset node
//                                      or communication, with 2000h/2 as saved
//                                      or written since; before the boot-up
//                                      message leaves, so it leaves at that rate
//                                      (IoNode::on_reset likewise with 2001h/2)
//   set filters   CanControl::set_filters
//                                      from Node::reset (after set_bitrate, before
//                                      the boot-up message) with the device's
//                                      acceptance ranges (Node::acceptance: the
//                                      node's consumed ids, the remote requests
//                                      it answers, the ranges of the device's
//                                      other services), and from the next
//                                      Node::process after a write changed what
//                                      the node consumes (1005h, 1400h-1403h,
//                                      1016h)
//
// So a change of 2000h/2 reaches the MCP2515 this way: the write is stored;
// the next reset communication (2001h = 1, NMT) calls Gateway::on_reset,
// which calls set_bitrate(2000h/2); on the Uno that is avr::CanPort::
// set_bitrate, which restarts the chip at the new rate.
//
// Acceptance: the device says what it must receive as CanIdRange {id, mask}
// (libcanard's CanardFilter, SocketCAN's can_filter), never as CANopen
// services; a port admits at least those frames. The SocketCAN port sets one
// kernel filter per range. The MCP2515 port plans its 2 masks / 6 filters
// for the ids of ranges of one id each, a superset when they do not fit
// exactly, and keeps the filters open for wider ranges or more ids than its
// planner takes (a network gateway's 580h-5FFh, 700h-77Fh); built for a
// device with a range wider than one id, it carries no planner at all
// (avr::CanPortFor, from the device's kWidestRange).
//
// Context rules (all ports):
//  * Every function is called from the context that calls the core (the main
//    loop), never from an interrupt; none is re-entered. A call may come
//    while the port's own code is on the stack: an NMT reset the port hands
//    in (CanInput::receive) sets bit rate and filters and sends the boot-up
//    message from inside that call. A port that takes frames or bytes in an
//    ISR queues them there and hands them in from the main loop
//    (CanInput::receive, SlaveCore::on_char).
//  * None blocks. send and write queue or refuse (false: the caller counts
//    the loss or retries); set_bitrate and set_filters take effect at once or
//    in steps the port runs from its own poll (the MCP2515 planner), and
//    until then the port lets every frame through (a superset is safe: the
//    device ignores what it does not consume; a subset loses frames).
//  * Arguments are borrowed for the call only: a port copies what it keeps
//    (the ranges of set_filters, the bytes of write).
//  * A null function pointer, or no CanControl table at all, means "not
//    supported here" (SocketCAN cannot set the bit rate; a test sink has no
//    filters; a port whose filters stay open); the core then skips the call.
//    Likewise a device without a use for controller events leaves
//    CanInput::controller_state null (the bridge).
#pragma once
#include <stdint.h>

#include "platform/flash.h"

namespace mb2co {

struct CanFrame;  // canopen/can_frame.h

/// Where frames to transmit go. `send` must not block. Returns false when
/// the port's transmit queue is full: the frame is dropped and the caller
/// decides whether to retry (services count such drops).
struct CanSink {
  bool (*send)(void* ctx, const CanFrame& frame);
  void* ctx;
};

/// Where a CAN port hands what its controller received: the device, which
/// routes each frame to its node core, its services or its application.
/// The port calls these from its poll, in arrival order, with the time the
/// frame was received (or the pass's time).
struct CanInput {
  /// Every received frame, whatever its id (the device ignores what it does
  /// not consume).
  void (*receive)(void* ctx, const CanFrame& frame, uint32_t now_us);
  /// The controller's events, ControllerEvent bits (never 0); `passive`:
  /// error passive or bus-off now. Null: the device takes none.
  void (*controller_state)(void* ctx, uint8_t events, bool passive, uint32_t now_us);
  void* ctx;
};

/// Standard frames a device must receive: a frame passes when
/// (key & mask) == (id & mask), where key is its 11-bit id with bit 11
/// (kCanRangeRemote) set for a remote frame. Mask bit 11 clear: data and
/// remote frames alike. Extended frames never pass (no device consumes them).
/// Ranges may overlap or repeat.
struct CanIdRange {
  uint16_t id;
  uint16_t mask;
};
/// The remote-frame bit in CanIdRange::id and ::mask.
constexpr uint16_t kCanRangeRemote = 0x800;
/// CanIdRange::mask for one id, data and remote frames alike.
constexpr uint16_t kCanRangeExact = 0x7FF;

/// How many standard ids `range` admits: 2^(id bits its mask leaves free);
/// the remote bit is no id bit.
constexpr uint16_t ids_in(const CanIdRange& range) {
  uint16_t ids = 1;
  for (uint16_t bit = 1; bit < kCanRangeRemote; bit = static_cast<uint16_t>(bit << 1)) {
    if ((range.mask & bit) == 0) ids = static_cast<uint16_t>(ids << 1);
  }
  return ids;
}
/// The most ids one of ranges[0..N) admits (a device's kWidestRange).
template <unsigned N>
constexpr uint16_t widest(const CanIdRange (&ranges)[N]) {
  uint16_t most = 0;
  for (unsigned i = 0; i < N; ++i) most = ids_in(ranges[i]) > most ? ids_in(ranges[i]) : most;
  return most;
}

/// The CAN controller's settings the core decides. Both get the CanSink's
/// ctx (one port object per controller). A port defines one constant table
/// of these, MB2CO_FLASH (flash on the AVR: no RAM); the core keeps a
/// pointer to it and reads it with flash_read().
struct CanControl {
  /// Bit rate in kbit/s (125, 250, 500 or 1000). The port restarts the
  /// controller when it differs from the rate in use (frames still waiting
  /// in it are lost) and keeps the filters last set.
  void (*set_bitrate)(void* ctx, uint16_t kbit);
  /// What the device must receive: ranges[0..count), count <=
  /// canopen::kMaxAcceptanceRanges (Node::acceptance). The port admits at
  /// least these frames. Replaces the previous set.
  void (*set_filters)(void* ctx, const CanIdRange* ranges, uint8_t count);
};

/// What a CAN port reports of its controller (CanInput::controller_state,
/// Node::on_controller_state): bits of an event mask, and the EMCY policy
/// lives in the core.
enum ControllerEvent : uint8_t {
  kControllerRxOverflow = 0x01,       ///< frames were lost: EMCY 8110h
  kControllerStateChanged = 0x02,     ///< error passive entered or left: 8120h
  kControllerBusOffRecovered = 0x08,  ///< back on the bus after bus-off: 8140h
};

namespace modbus {

/// Where a Modbus/RTU port sends bytes. `write` gets one complete ADU (CRC
/// included) per call, in transmission order; it may queue the bytes but
/// must not keep `data` after returning (the buffer is reused for the next
/// frame). Returns false when the bytes could not be queued: the response is
/// lost and counted.
struct ByteSink {
  bool (*write)(void* ctx, const uint8_t* data, uint16_t length);
  void* ctx;
};

}  // namespace modbus

namespace canopen {

/// Byte-addressed non-volatile storage (EEPROM on the Uno, a file on Linux,
/// RAM in tests); the core decides the layout: two slots, each with a CRC
/// (param_storage.h). False: the access failed.
struct ParamStorage {
  bool (*read)(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
  bool (*write)(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);
  /// Every write before it is durable before any write after it (a file:
  /// fsync). nullptr when writes reach the medium in order anyway (EEPROM).
  bool (*barrier)(void* ctx);
  void* ctx;
  /// True when a write of one byte would start at once (the Uno: no EEPROM
  /// byte being programmed, EEPE clear; it takes 3.3 ms). A save (1010h)
  /// writes one byte per write() call and only when this says so, a few per
  /// pass of the loop (canopen::ParamSave), so the loop never waits for the
  /// medium. nullptr: always ready (a file, RAM). Loads and 1011h do not ask.
  bool (*ready)(void* ctx);
};

}  // namespace canopen

namespace gateway {

/// Everything a gateway needs from its platform. Copied by the Gateway's
/// constructor, except *storage, which must outlive the Gateway.
struct GatewayPorts {
  CanSink can;
  modbus::ByteSink serial;
  const canopen::ParamStorage* storage;  ///< may be null (nothing persists)
  uint32_t serial_baud;                  ///< for the RTU t1.5/t3.5 timing
  /// MB2CO_FLASH table (CanControl); null: neither bit rate nor filters.
  const CanControl* can_control = nullptr;
};

}  // namespace gateway
}  // namespace mb2co
