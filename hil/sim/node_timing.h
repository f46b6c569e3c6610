// The cost model of a simulated station's main loop: when its passes run and
// how long each takes (measured on an ATmega328P by default). NodeStation
// schedules its passes with it.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "sim/event_queue.h"

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
  uint32_t uart_rx_bytes = 64;  ///< Arduino serial receive ring
  /// True: the UART interrupt stamps each character at its end (what the
  /// RTU framer wants). False: characters are stamped when a pass reads
  /// them, and the slave's t1.5 check is off (a loop is longer than t1.5).
  bool isr_stamps = true;
  size_t can_rx_buffers = 2;  ///< MCP2515 RXB0 + RXB1
  /// The port programs the MCP2515's masks and filters (mcp2515::
  /// plan_filters) for the gateway's acceptance ranges (Node::acceptance,
  /// handed over by CanControl::set_filters at each reset and after a change;
  /// open when they admit more ids than the planner takes).
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

}  // namespace sim
}  // namespace mb2co
