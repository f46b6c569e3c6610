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
#pragma once
#include <stdint.h>
#include <string.h>

#include <functional>
#include <memory>
#include <vector>

#include "gateway/gateway.h"
#include "sim/can_bus.h"
#include "sim/event_queue.h"
#include "sim/rng.h"
#include "sim/serial_link.h"

namespace mb2co {
namespace sim {

/// When passes run and how long each takes. Processing time of one pass =
/// pass_ns + U(0, jitter_ns) + frame_ns per CAN frame handed in + byte_ns
/// per serial character handed in + the cost of the Modbus request it
/// answered: request_ns + per register or bit item_ns (+ write_ns for a
/// write) + item_address_ns x the first address (the register map is walked
/// once per request, from its start). Defaults: uno_timing().
struct NodeTiming {
  /// 0: back to back (Arduino loop(): the next pass starts when one ends);
  /// > 0: a pass starts every loop_ns, or when the previous one ends if later.
  SimNs loop_ns = 0;
  // Measured with firmware/avr/measure-pass-time.sh (docs/performance.md,
  // "Gateway on the Uno"): idle pass 180..184 us, 412 us when a TPDO is built
  // and sent; a heartbeat / RPDO frame +348 / +452..488 us; 8 characters
  // 132 us; FC 04 of register 0 416 us, of 18 736 us, of 0..22 1,840 us;
  // FC 06 868..916 us (the second of two identical requests each time).
  SimNs pass_ns = 184 * kNsPerUs;
  SimNs jitter_ns = 230 * kNsPerUs;
  SimNs frame_ns = 490 * kNsPerUs;
  SimNs byte_ns = 17 * kNsPerUs;
  SimNs request_ns = 162 * kNsPerUs;
  SimNs write_ns = 500 * kNsPerUs;
  SimNs item_ns = 70 * kNsPerUs;
  SimNs item_address_ns = 18 * kNsPerUs;
  uint32_t uart_rx_bytes = 64;          ///< Arduino serial receive ring
  /// True: the UART interrupt stamps each character at its end (what the
  /// RTU framer wants). False: characters are stamped when a pass reads
  /// them, and the slave's t1.5 check is off (a loop is longer than t1.5).
  bool isr_stamps = true;
  size_t can_rx_buffers = 2;            ///< MCP2515 RXB0 + RXB1
  /// The port programs the MCP2515's masks and filters (mcp2515::
  /// plan_filters) with the COB-IDs the gateway consumes, after each reset.
  bool can_filters = true;
  /// Speed only, same results: the firmware is not called in a pass that
  /// provably does nothing (the rule: NodeStation, "Idle passes"). Off =
  /// every pass calls the firmware.
  bool skip_idle = true;
};

/// The ATmega328P at 16 MHz running this firmware (measured with simavr on
/// the shared code, firmware/avr/measure-pass-time.sh): back-to-back loop.
NodeTiming uno_timing();
/// A fast node: a pass every 1 ms taking 100..300 µs whatever it does (the
/// firmware loop the timing analysis assumes by default).
NodeTiming fast_timing();

/// Processing time of a pass that answers Modbus request `req` (an ADU),
/// without the per-pass, per-frame and per-byte parts.
SimNs request_cost(const NodeTiming& t, const uint8_t* req, size_t len);
/// Longest processing time of any pass that hands in at most `frames` CAN
/// frames and `bytes` characters and answers a request costing `request`.
SimNs max_pass_ns(const NodeTiming& t, size_t frames, size_t bytes, SimNs request);

/// Watched OD state of a gateway, refreshed after every pass.
struct NodeState {
  uint8_t nmt = 0;
  uint8_t run = 0;          ///< 2100h/2
  uint16_t stop2_count = 0; ///< 2100h/3
  uint8_t prev_status = 0;  ///< 2110h/3 (0 unknown, 1 alive, 2 none)
  uint8_t next_status = 0;  ///< 2120h/3
  uint8_t prev_run = 0;     ///< 2110h/1
  uint8_t next_run = 0;     ///< 2120h/1
  bool operator==(const NodeState& o) const {
    return nmt == o.nmt && run == o.run && stop2_count == o.stop2_count &&
           prev_status == o.prev_status && next_status == o.next_status &&
           prev_run == o.prev_run && next_run == o.next_run;
  }
  bool operator!=(const NodeState& o) const { return !(*this == o); }
};

/// Idle passes (NodeTiming::skip_idle). A pass still takes its time, draws
/// its jitter and hands in the serial characters that arrived, but it does
/// not call Gateway::process when that call provably changes nothing:
///  * the last call changed nothing (no frame, byte or LED out, no send
///    refused, no OD value and no watched state changed): so the firmware
///    waits only on its timers and on input;
///  * no timer is due yet: the pass starts before wake_ns_, a lower bound of
///    every deadline the firmware keeps (compute_wake; a configuration it
///    cannot bound disables skipping);
///  * no CAN frame and no button change came since that call;
///  * serial characters, if any, went to the Modbus framer (on_serial_byte,
///    as in every pass) without closing a frame (the slave's counters are
///    unchanged), and the frame's t3.5 deadline (SlaveCore::deadline) is
///    after the pass start; wake_ns_ is lowered to it. The framer is the only
///    part characters reach, and process() leaves it alone before t3.5.
/// Then process() would return the same LEDs and leave every state as it
/// is, so not calling it gives the same run. Characters taken are therefore
/// no change in this sense either. Determinism.SkippingIdlePassesChangesNothing
/// (tests/sim) compares whole runs with skipping on and off.
class NodeStation : public Handler {
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
  void attach_serial(UartChannel* rx) { rx_ = rx; }
  /// Serial output: bytes leave at the end of the pass that produced them.
  std::function<void(const uint8_t* data, uint16_t n)> serial_out;

  /// Raw button levels (gateway::Button bits), sampled by the next pass.
  void set_buttons(uint8_t raw) { buttons_ = raw; }
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
  uint64_t uart_overruns() const { return uart_overruns_; }
  /// Firmware clock (µs since power-on) at simulated time `t`.
  uint32_t micros_at(SimNs t) const { return static_cast<uint32_t>((t - boot_ns_) / kNsPerUs); }

  void on_event(uint32_t code, uint64_t arg) override;

 private:
  enum Code : uint32_t { kPass, kRelease };
  static bool can_send(void* ctx, const CanFrame& f);
  static bool serial_send(void* ctx, const uint8_t* data, uint16_t n);
  static bool eeprom_read(void* ctx, uint16_t at, uint8_t* data, uint16_t n);
  static bool eeprom_write(void* ctx, uint16_t at, const uint8_t* data, uint16_t n);
  void make_gateway();
  void pass();
  void release();
  /// Schedules the release of the pass's outputs; returns the next pass's time.
  SimNs finish_pass(uint8_t leds, SimNs proc);
  /// Hands the characters complete by `t` to the firmware; returns their cost.
  SimNs take_serial(SimNs t, uint32_t now_us);
  /// What changes when the Modbus slave closes a frame (each frame is
  /// counted in CPT1, CPT2 or CPT8; a restart leaves listen-only mode).
  struct SlaveSnapshot {
    modbus::DiagCounters counters;
    modbus::LinkStats stats;
    bool listen_only;
    bool operator==(const SlaveSnapshot& o) const {
      return memcmp(&counters, &o.counters, sizeof counters) == 0 &&
             memcmp(&stats, &o.stats, sizeof stats) == 0 && listen_only == o.listen_only;
    }
  };
  SlaveSnapshot slave_snapshot() const;
  /// After characters reached an idle firmware: true when the slave's t3.5
  /// deadline is still ahead of `t` (wake_ns_ lowered to it).
  bool serial_idle(SimNs t, uint32_t now_us);
  /// Lowers `wake` to just before `exact`, a deadline of the firmware's
  /// (1 µs margin for the µs clock); one already behind `t` was handled.
  static void lower_wake(SimNs& wake, SimNs t, SimNs exact);
  NodeState read_state();
  /// Acceptance filters for what the OD says this node consumes.
  void plan_filters();
  /// After a pass that changed nothing: the earliest time at which a pass
  /// without new input could do something (a lower bound from the firmware's
  /// timers as the OD configures them and as their frames were seen).
  SimNs compute_wake(SimNs t);
  void read_wake_config();
  SimNs at_micros(SimNs t, uint32_t now_us, uint32_t at_us) const;

  EventQueue& q_;
  CanController can_;
  int index_;
  uint32_t baud_;
  NodeTiming timing_;
  Rng rng_;
  std::vector<uint8_t> eeprom_;
  canopen::ParamStorage storage_;
  std::unique_ptr<gateway::Gateway> gw_;
  bool bench_ = false;  ///< commissioning: outputs go nowhere
  uint32_t generation_ = 0;
  SimNs boot_ns_ = 0;
  uint8_t buttons_ = 0;
  uint8_t leds_ = 0;
  uint8_t leds_out_ = 0;  ///< LED levels of the pass in progress
  NodeState state_;
  UartChannel* rx_ = nullptr;
  uint64_t uart_overruns_ = 0;
  std::vector<CanFrame> tx_pending_;   ///< accepted in this pass, queued at its end
  std::vector<uint8_t> serial_pending_;
  std::vector<uint8_t> frame_;  ///< characters of the request being received
  SimNs last_char_ns_ = 0;
  SimNs frame_gap_ns_ = 0;      ///< a silence this long starts a new frame
  bool booting_ = false;  ///< the next pass is the first after power-on
  uint64_t passes_ = 0;
  uint64_t firmware_calls_ = 0;
  uint16_t rows_[7] = {};
  // Idle-pass elision (skip_idle, "Idle passes" above).
  bool quiet_ = false;          ///< the last firmware call changed nothing
  bool refused_ = false;        ///< a CAN send was refused in this pass
  SimNs wake_ns_ = 0;           ///< passes before this may be skipped
  SimNs holdoff_ns_ = 0;        ///< no skipping before (after power-on, NMT changes)
  SimNs prev_pass_ns_ = 0;      ///< time of the grid pass before the current one
  SimNs pass_ns_ = 0;           ///< time of the pass in progress
  uint8_t last_buttons_ = 0;
  SimNs buttons_changed_ns_ = 0;
  SimNs hb_sent_prev_ns_ = 0;   ///< grid pass before the last heartbeat sent (0: none)
  SimNs tpdo_sent_ns_[4] = {};  ///< pass of the last send of each TPDO (0: none)
  uint16_t tpdo_cob_rows_[4] = {};
  struct WakeRows {  ///< OD rows compute_wake reads (found once per gateway)
    uint16_t sync_period, emcy_inhibit, debounce, watchdog, heartbeat, guard_time, life_factor;
    uint16_t tpdo_type[4], tpdo_inhibit[4], tpdo_event[4], tpdo_map[4], rpdo_event[4];
    uint16_t consumer[4];
  } wr_ = {};
  SimNs hb_heard_ns_[128] = {}; ///< pass that handed in the last heartbeat of a node
  /// The timer settings compute_wake needs, decoded from the OD. Valid while
  /// no OD value changed (any change in a pass clears wc_valid_).
  struct WakeConfig {
    bool untracked;  ///< a timer compute_wake cannot bound is configured
    SimNs debounce_ns, heartbeat_ns;
    uint32_t watchdog_us;                        ///< 2000h/9 (0: off)
    SimNs tpdo_inhibit_ns[4], tpdo_event_ns[4];  ///< both 0: TPDO off or untimed
    SimNs consumer_ns[4];                        ///< 0: consumer off
    uint8_t consumer_node[4];
  } wc_ = {};
  bool wc_valid_ = false;
  uint16_t requests_seen_ = 0;  ///< Modbus requests the line application has seen
  SimNs request_seen_ns_ = 0;   ///< pass in which it saw the last new one (0: none)
  SimNs sdo_heard_ns_ = 0;      ///< pass that handed in the last SDO request (0: none)
  uint8_t* values_ = nullptr;   ///< the OD's RAM value block
  std::vector<uint8_t> values_before_;
};

}  // namespace sim
}  // namespace mb2co
