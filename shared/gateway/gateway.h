// One station's Arduino: CANopen node (gateway OD), Modbus/RTU slave whose
// registers are windows onto that OD, and the RUN/STOP2 line application.
// The same object runs on the Uno, in the Linux build (mb2co-node) and in the
// line simulator: ports hand in CAN frames, serial bytes, button levels and
// time, and take out CAN frames, serial bytes and LED levels.
// Memory: the caller owns the Gateway (static on the Uno); no heap.
#pragma once
#include <stdint.h>

#include "canopen/node.h"
#include "gateway/gateway_od.h"
#include "gateway/line_app.h"
#include "gateway/network_slot.h"  // FC 2Bh/0Dh where the profile has it
#include "gateway/od_register_bank.h"
#include "modbus/slave.h"
#include "platform/device_port.h"  // GatewayPorts: the platform contract

namespace mb2co {
namespace gateway {

/// What FC 2Bh/0Dh's network service receives besides what the node
/// consumes, where the profile has it (profile::kNetwork): every SDO
/// response (580h-5FFh: its SDO client talks to any node) and every
/// heartbeat (700h-77Fh: its network view).
constexpr CanIdRange kNetworkServiceRanges[] MB2CO_FLASH = {{0x580, 0x780}, {0x700, 0x780}};

/// Longest frame a request the register maps can cover needs: the response
/// to a read of a whole map of 32-bit entries (2 registers each); the longest
/// such write (FC 10h/17h) is shorter. Every request that can succeed fits.
constexpr uint16_t kMapFrameBytes = static_cast<uint16_t>(
    1u + 2u + 2u * 2u * (kInputMapSize > kHoldingMapSize ? kInputMapSize : kHoldingMapSize) +
    modbus::kCrcBytes);
/// The Modbus slave's frame buffer: the protocol's 256 bytes, but on the Uno
/// only what the maps need (longer requests are lost as overruns: slave.h).
#ifdef __AVR__
constexpr uint16_t kModbusFrameBytes = kMapFrameBytes;
#else
constexpr uint16_t kModbusFrameBytes = modbus::kMaxAduBytes;
#endif

/// The state of a Gateway that starts at zero: one block, value-initialised
/// first by the Gateway's constructor (one zero-fill instead of one for the
/// value block, one for the line application and a store per member).
struct GatewayState {
  od::GatewayValues values_;
  LineApp line_;
  uint32_t now_us_;     ///< time of the frame or call being handled
  bool start_pending_;  ///< self-starting (2000h/8): NMT start after boot-up
};

class Gateway : private GatewayState {
 public:
  explicit Gateway(const GatewayPorts& ports);

  /// Power-on. Node id, bit rate and Modbus address come from the saved
  /// parameters (2000h), or `default_node_id` when none are saved.
  void start(uint32_t now_us, uint8_t default_node_id = 1);
  /// A received frame: to the node, and to FC 2Bh/0Dh's service (its SDO
  /// client's responses, the heartbeats of its view). Inline, below.
  void on_can_frame(const CanFrame& f, uint32_t now_us);
  /// The gateway as a CAN port's device (platform/device_port.h): every
  /// frame to on_can_frame, the controller's events to the node.
  CanInput can_input() { return CanInput{&Gateway::receive, &Gateway::controller_state, this}; }
  /// The network service's widest range in ids (0: not in this image).
  static constexpr uint16_t kNetworkWidest = profile::kNetwork ? widest(kNetworkServiceRanges) : 0;
  /// The most ids one of the gateway's acceptance ranges admits (a port's
  /// choice of filters: avr::CanPortFor).
  static constexpr uint16_t kWidestRange =
      kNetworkWidest > canopen::Node::kWidestRange ? kNetworkWidest : canopen::Node::kWidestRange;
  /// A received character: to the Modbus slave. Inline, below.
  void on_serial_byte(uint8_t byte, uint32_t byte_us);
  /// Runs everything due at `now_us` with the raw button levels (Button bits,
  /// 1 = pressed); returns the LED levels to drive (Led bits).
  uint8_t process(uint32_t now_us, uint8_t raw_buttons);
  /// When process() must run next, in the form and with the invariant of
  /// canopen::Node::next_deadline (false: nothing pending; else *at_us, the
  /// earliest deadline, now_us when work waits): process() called at *at_us,
  /// or after any later input (a CAN frame, a serial byte, other button
  /// levels), does everything due; called earlier it changes nothing
  /// observable. Contributions: the node's timers, the Modbus slave's frame
  /// end (t3.5), the line application's debounce (2000h/6), Modbus watchdog
  /// (2000h/9, from power-on), blink of an unknown neighbour and outputs to
  /// refresh, the self-start after a reset (2000h/8). It also holds right
  /// after on_serial_byte(): characters that only feed the framer move the
  /// frame end, and a request they complete (a late character closes the
  /// previous frame) is counted by the slave, which makes the line
  /// application's refresh due now. For a caller that sleeps or skips idle
  /// passes (the line simulator); the Uno runs every pass.
  bool next_deadline(uint32_t now_us, uint32_t* at_us) const;

  uint8_t node_id() const { return node_.node_id(); }
  /// What the gateway must receive (Node::acceptance: the node's ids and,
  /// with FC 2Bh/0Dh, kNetworkServiceRanges).
  uint8_t acceptance(CanIdRange* ranges) const { return node_.acceptance(ranges); }
  canopen::Node& node() { return node_; }
  canopen::ObjectDictionary& od() { return od_; }
  modbus::SlaveCore& modbus_slave() { return slave_; }

 private:
  friend struct GatewayHandlers;  // the OD's handler of the RUN command (gateway_od.h)
  static void on_reset(void* ctx, canopen::NmtReset kind);
  static void on_heartbeat(void* ctx, uint8_t node_id, canopen::HbEvent event, uint8_t nmt);
  static void on_rpdo(void* ctx, uint8_t n);
  /// The line application's stamps on the node's common clock once TIME
  /// set it, and 2300h/4 (profile::kTime; no code without it).
  void follow_common_clock();
  static void receive(void* ctx, const CanFrame& f, uint32_t now_us) {
    static_cast<Gateway*>(ctx)->on_can_frame(f, now_us);
  }
  static void controller_state(void* ctx, uint8_t events, bool passive, uint32_t now_us) {
    static_cast<Gateway*>(ctx)->node_.on_controller_state(events, passive, now_us);
  }

  canopen::ObjectDictionary od_;
  canopen::Node node_;
  OdRegisterBank bank_;
  OdDeviceIdentity identity_;
  modbus::SlaveWithFrame<kModbusFrameBytes> slave_;
  // FC 2Bh / MEI 0Dh: the whole network from Modbus (network_slot.h:
  // the service, or nothing where the profile leaves it out).
  NetworkSlot net_;

 public:
  const NetworkSlot& network() const { return net_; }
};

inline void Gateway::follow_common_clock() {
#if MB2CO_CONFIG_TIME
  const canopen::TimeStamp& t = node_.time();
  line_.set_stamp_offset(t.clock_set() ? t.offset_us() : 0);
  values_.x2300_4_commonClockSetUs = t.clock_set() ? t.set_at_us() : 0;
#endif
}

inline void Gateway::on_can_frame(const CanFrame& f, uint32_t now_us) {
  // The time an RPDO callback stamps (2300h/3) is the frame's, not that of
  // the last process(): a caller that skips idle passes stamps the same.
  now_us_ = now_us;
  node_.receive(f, now_us);
  net_.on_can_frame(f, now_us);
}

inline void Gateway::on_serial_byte(uint8_t byte, uint32_t byte_us) {
  now_us_ = byte_us;  // a late frame end runs a network request from in here
  slave_.on_byte(byte, byte_us);
}

}  // namespace gateway
}  // namespace mb2co
