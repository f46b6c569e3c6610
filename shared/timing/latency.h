// End-to-end button-to-LED bound of seed 000 §11, best and worst case, for
// the two paths of the latency lab:
//   Modbus only:      button and LED on the PC's own Arduino (A);
//   Modbus + CANopen: button and LED on another Arduino (B), whose TPDO1
//                     reaches A, the PC reads it from A and writes the LED
//                     state to A, whose TPDO1 carries it back to B.
// The result is a list of named terms (the breakdown) whose sums are the
// bounds; the simulator and the lab compare measurements term by term.
//
// Model (each assumption is one term): every outside event (a settled button,
// a CAN frame, the end of a Modbus frame) waits at most one firmware loop
// pass to be noticed, and what follows inside that Arduino happens in the
// same pass; a pending TPDO held back by its inhibit time goes out at the
// first pass after the inhibit time ends; the PC runs read-compute-write once
// per cycle. All times in ns; lower bounds round down, upper bounds up.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "timing/rtu_timing.h"

namespace mb2co {
namespace timing {

struct LatencyParams {
  // --- operator panel and firmware (both Arduinos alike)
  uint32_t debounce_us = 20000;  ///< a press counts after being stable this long
  uint32_t fw_loop_us = 1000;    ///< longest time between two main-loop passes
  uint32_t inhibit_us = 10000;   ///< TPDO inhibit time (1800h sub3 · 100 µs); 0 = none
  // --- PC control loop
  uint32_t pc_cycle_us = 10000;  ///< cycle period, start to start; 0 = back to back
  uint32_t pc_compute_us = 0;    ///< from the read response's end to the write request
  uint32_t master_end_us = 0;    ///< PC noticing a response ended (0: length predicted)
  // --- serial link (Modbus RTU)
  SerialFormat serial;                          ///< 115200 baud 8E1 by default
  bool slave_waits_t35 = true;                  ///< slave detects a request's end by t3.5 silence
  RtuExchange read = read_bits_exchange(1);     ///< FC 02, the button
  RtuExchange write = write_single_exchange();  ///< FC 05, the LED
  // --- CAN, per hop (Modbus + CANopen path only); fill from the analysis
  uint64_t can_up_best_ns = 0;     ///< B→A TPDO: frame without stuffing and IFS
  uint64_t can_up_worst_ns = 0;    ///< B→A TPDO: worst-case response time R
  uint64_t can_down_best_ns = 0;   ///< A→B TPDO: frame without stuffing and IFS
  uint64_t can_down_worst_ns = 0;  ///< A→B TPDO: worst-case response time R
};

/// One contribution to the latency.
struct LatencyTerm {
  const char* name;  ///< stable key (docs/timing.md lists them)
  uint64_t best_ns;
  uint64_t worst_ns;
};

constexpr size_t kMaxLatencyTerms = 16;

struct LatencyBound {
  LatencyTerm terms[kMaxLatencyTerms];
  size_t count;       ///< terms in use, in the order the signal passes them
  uint64_t best_ns;   ///< Σ best_ns
  uint64_t worst_ns;  ///< Σ worst_ns
};

/// Appends a term and adds it to the sums (a full bound stays as it is: the
/// fixed paths never reach kMaxLatencyTerms). Start from LatencyBound{}.
void add_latency_term(LatencyBound& b, const char* name, uint64_t best_ns, uint64_t worst_ns);

/// The PC's read-compute-write cycle on the serial line.
struct PollCycle {
  TransactionTiming read;
  TransactionTiming write;
  uint64_t busy_best_ns;   ///< read + compute + write, slave answering at once
  uint64_t busy_worst_ns;  ///< the same with one firmware loop per turnaround
  uint64_t period_ns;      ///< max(pc_cycle, busy_worst): the cycle actually run
};

/// Requires serial_format_valid(p.serial).
PollCycle poll_cycle(const LatencyParams& p);

LatencyBound modbus_only_latency(const LatencyParams& p);
LatencyBound modbus_canopen_latency(const LatencyParams& p);
/// Seed 000 §11 "simpler alternative": the process control software runs on
/// Arduino A and the button and LED are on Arduino B; only CANopen carries
/// the data. B's TPDO (button) reaches A, A's control pass writes the LED
/// object, A's TPDO carries it back to B: the Modbus + CANopen path without
/// the serial round (no PC in the loop). Uses the CAN hops and inhibit of p.
LatencyBound arduino_control_latency(const LatencyParams& p);

/// Best case of one CAN hop: the frame without stuff bits and without the
/// interframe space (the receiver has it at the end of EOF), rounded down.
uint64_t can_hop_best_ns(bool extended, uint8_t dlc, uint32_t bitrate_bps);

}  // namespace timing
}  // namespace mb2co
