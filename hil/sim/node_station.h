// One station's Arduino in virtual time: the real gateway firmware core
// (shared/gateway) with an MCP2515-like controller on the simulated bus, a
// UART receive ring, buttons, LEDs and an EEPROM.
//
// The main loop runs passes back to back like Arduino's loop() (or one per
// loop_ns, see NodeTiming). A pass hands in the serial characters and CAN
// frames that arrived before it, samples the buttons and runs
// Gateway::process at its start time; it lasts a processing time given by a
// cost model (NodeTiming: measured on an ATmega328P by default), and the CAN
// frames, serial bytes and LED levels it produced leave at its end.
// Transmit-buffer space is judged at the start of the pass (a full MCP2515
// refuses, the firmware retries). The firmware clock (micros()) starts at 0
// at each power-on.
//
// Files, one concern each: node_station.cpp the pass scheduler (passes,
// idle-pass skipping, release of outputs); node_timing.* the cost model;
// uart_ring.* the serial receive ring; node_gateway.cpp the firmware
// adapter (the gateway on the station's ports, commissioning, watched
// state); eeprom.h the EEPROM.
#pragma once
#include <stdint.h>

#include <functional>
#include <memory>
#include <vector>

#include "gateway/gateway.h"
#include "sim/can_bus.h"
#include "sim/eeprom.h"
#include "sim/event_queue.h"
#include "sim/node_timing.h"
#include "sim/rng.h"
#include "sim/serial_link.h"
#include "sim/uart_ring.h"

namespace mb2co {
namespace sim {

/// Watched OD state of a gateway, refreshed after every pass.
struct NodeState {
  uint8_t nmt = 0;
  uint8_t run = 0;           ///< 2100h/2
  uint16_t stop2_count = 0;  ///< 2100h/3
  uint8_t prev_status = 0;   ///< 2110h/3 (0 unknown, 1 alive, 2 none; +80h no TPDO1 yet)
  uint8_t next_status = 0;   ///< 2120h/3
  uint8_t prev_run = 0;      ///< 2110h/1
  uint8_t next_run = 0;      ///< 2120h/1
  bool operator==(const NodeState& o) const {
    return nmt == o.nmt && run == o.run && stop2_count == o.stop2_count && prev_status == o.prev_status &&
           next_status == o.next_status && prev_run == o.prev_run && next_run == o.next_run;
  }
  bool operator!=(const NodeState& o) const { return !(*this == o); }
};

/// Idle passes (NodeTiming::skip_idle). A pass still takes its time, draws
/// its jitter and hands in the serial characters that arrived, but it does
/// not call Gateway::process when the core says that call would change
/// nothing: the pass starts before wake_ns_, the time at which the firmware
/// clock reaches Gateway::next_deadline (asked after every call, and again
/// after characters reached an otherwise idle firmware), and no CAN frame and
/// no button change came since the last call. Characters are input: handed
/// in (as in every pass) they may move the deadline (the slave's t3.5) or
/// make work (a request closed by a late character, a response sent from
/// on_char): then the pass runs. The invariant of next_deadline (process()
/// earlier than it changes nothing observable) makes the run the same as
/// with every pass calling the firmware; Determinism.SkippingIdlePasses*
/// (tests/sim) compare whole runs with skipping on and off.
class NodeStation final : public Sleeper {
 public:
  NodeStation(EventQueue& queue, CanBus& bus, int index, uint32_t baud, const NodeTiming& timing,
              uint64_t seed);

  int index() const { return index_; }
  /// On the bench before the line is assembled: power on alone (frames go
  /// nowhere), let `configure` write the OD as a technician would by SDO,
  /// save (1010h) into the EEPROM, power off. Node id = index + 1.
  void commission(const std::function<void(canopen::ObjectDictionary&)>& configure);
  void power_on();
  void power_off();
  bool powered() const { return gw_ != nullptr; }

  /// Where serial characters come from (the link's PC-to-node channel).
  void attach_serial(UartChannel* rx) {
    rx_ = rx;
    if (rx != nullptr) rx->reader = this;  // a character on an empty line moves the wake floor
    floor_moved();
  }
  /// Serial output: bytes leave at the end of the pass that produced them.
  std::function<void(const uint8_t* data, uint16_t n)> serial_out;

  /// Raw button levels (gateway::Button bits), sampled by the next pass.
  void set_buttons(uint8_t raw) {
    buttons_ = raw;
    floor_moved();
  }
  uint8_t buttons() const { return buttons_; }
  uint8_t leds() const { return leds_; }
  const NodeState& state() const { return state_; }

  /// LED levels changed (called at the end of the pass, now() = change time).
  std::function<void(int station, uint8_t leds)> on_leds;
  /// Watched OD state changed (called after the pass that changed it).
  std::function<void(int station, const NodeState& before, const NodeState& after)> on_state;

  gateway::Gateway& gateway() { return *gw_; }
  CanController& can() { return can_; }
  uint64_t passes() const { return passes_; }
  /// Passes that called the firmware (the others were provably idle).
  uint64_t firmware_calls() const { return firmware_calls_; }
  uint64_t uart_overruns() const { return uart_.overruns(); }
  /// Firmware clock (µs since power-on) at simulated time `t`.
  uint32_t micros_at(SimNs t) const { return static_cast<uint32_t>((t - boot_ns_) / kNsPerUs); }

  void on_event(uint32_t code, uint64_t arg) override;
  /// Sleeper: the next pass is idle before this time (0: not idle, an input
  /// came). The rule of "Idle passes": before wake_ns_, no CAN frame, no
  /// button change, no serial character complete.
  SimNs wake_floor() const override;
  /// Sleeper: idle passes from `t` on, before `limit` (each one's jitter
  /// drawn as pass() draws it).
  SimNs idle_passes(SimNs t, SimNs limit, uint64_t* count) override;
  /// CanControl::set_filters: the controller admits what the gateway's
  /// acceptance ranges admit (planned as the Uno plans them).
  static void set_filters(void* ctx, const CanIdRange* ranges, uint8_t count);

 private:
  enum Code : uint32_t { kPass, kRelease };
  static bool can_send(void* ctx, const CanFrame& f);
  static bool serial_send(void* ctx, const uint8_t* data, uint16_t n);
  void make_gateway();
  void pass();
  void release();
  /// Schedules the release of the pass's outputs; returns the next pass's time.
  SimNs finish_pass(uint8_t leds, SimNs proc);
  /// The next pass at `t_ns`: asleep (run in place while idle) when idle
  /// passes may be skipped, else through the queue.
  void next_pass(SimNs t_ns);
  /// Hands the characters complete by `t` to the firmware; returns their cost.
  SimNs take_serial(SimNs t, uint32_t now_us);
  /// wake_ns_ = when the firmware clock reaches Gateway::next_deadline, asked
  /// at `t` (never: no deadline pending).
  void ask_deadline(SimNs t, uint32_t now_us);
  /// ask_deadline() after characters that only fed the framer (nothing
  /// sent, nothing due): they move the slave's frame end and nothing else
  /// of the core (Gateway::next_deadline), unless they completed a request
  /// (the slave counted it: the line application's refresh is due). So
  /// wake_ns_ = the earlier of the rest's deadline, as last asked with no
  /// frame in progress, and the frame's end; else the whole question.
  void ask_deadline_after_chars(SimNs t, uint32_t now_us);
  NodeState read_state() const;
  /// Watched entry k (the order of NodeState) read from its value bytes.
  uint32_t watched(size_t k) const;
  /// When micros() reaches `at_us`, seen from the pass at `t` (micros() = now_us).
  SimNs at_micros(SimNs t, uint32_t now_us, uint32_t at_us) const;

  EventQueue& q_;
  CanController can_;
  int index_;
  uint32_t baud_;
  NodeTiming timing_;
  Rng rng_;
  Eeprom eeprom_;  ///< survives power cycles (1010h saves here)
  std::unique_ptr<gateway::Gateway> gw_;
  bool bench_ = false;  ///< commissioning: outputs go nowhere
  uint32_t generation_ = 0;
  SimNs boot_ns_ = 0;
  uint8_t buttons_ = 0;
  uint8_t leds_ = 0;
  uint8_t leds_out_ = 0;  ///< LED levels of the pass in progress
  NodeState state_;
  UartChannel* rx_ = nullptr;
  UartRing uart_;                     ///< the Arduino's serial receive ring
  std::vector<CanFrame> tx_pending_;  ///< accepted in this pass, queued at its end
  std::vector<uint8_t> serial_pending_;
  bool booting_ = false;  ///< the next pass is the first after power-on
  uint64_t passes_ = 0;
  uint64_t firmware_calls_ = 0;
  static constexpr size_t kWatched = 7;
  /// The watched entries' value bytes in the gateway's OD (little-endian,
  /// 1 or 2 bytes each), resolved once per power-on: no OD lookup per pass.
  const uint8_t* watched_[kWatched] = {};
  uint8_t watched_size_[kWatched] = {};
  // Idle-pass elision (skip_idle, "Idle passes" above).
  SimNs wake_ns_ = 0;           ///< passes before this may be skipped
  uint8_t last_buttons_ = 0;    ///< the levels the firmware last sampled
  bool rest_known_ = false;     ///< rest_wake_ns_ holds (ask_deadline_after_chars)
  SimNs rest_wake_ns_ = 0;      ///< the core's deadline without the slave's frame end
  uint32_t rest_messages_ = 0;  ///< the slave's server_messages when it was asked
};

}  // namespace sim
}  // namespace mb2co
