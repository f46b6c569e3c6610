// The analytical button-to-LED bound (shared/timing, seed 000 §2.9–2.13, §11)
// for exactly the line being simulated: CAN message set read from the
// commissioned Object Dictionaries (every enabled TPDO and heartbeat), the
// firmware loop from the node timing model, the PC cycle with its jitter.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "sim/lab_window.h"
#include "sim/line.h"
#include "timing/latency.h"
#include "timing/message_set.h"

namespace mb2co {
namespace sim {

struct LabBound {
  bool ok = false;
  std::string error;  ///< why there is no bound (unbounded RTA, ...)
  timing::LatencyParams params;
  timing::LatencyBound bound = {};
  std::vector<timing::MessageSpec> messages;  ///< the line's CAN set, priority order
  SimNs pass_max_ns = 0;                      ///< longest pass of a lab station
  SimNs step_ns = 0;  ///< event → end of the pass that handles it (fw_loop: message jitter, alternative)
  // The bound per kind of pass (lab_bound; docs/timing.md §9), frames apart:
  SimNs plain_pass_ns = 0;  ///< longest pass with no frame, character or request
  SimNs read_pass_ns = 0;   ///< longest pass that answers the PC's read
  SimNs write_pass_ns = 0;  ///< longest pass that answers the PC's write
  SimNs window_ns = 0;      ///< the window the frames are counted in
  uint32_t frames_pc = 0;   ///< frames the PC's Arduino takes into the path's passes
  uint32_t frames_led = 0;  ///< the same for the button's and LED's Arduino (Modbus + CANopen)
};

/// Longest time from an outside event to the end of the pass that handles
/// it, for passes of at most `pass_max_ns`: one pass in progress (or one
/// loop period) plus the handling pass.
SimNs firmware_step_ns(const NodeTiming& t, SimNs pass_max_ns);

/// Bound for the lab of `line` (config().lab_pc / lab_remote set):
/// `remote` = Modbus + CANopen path (button and LED on lab_remote), else
/// Modbus only (button and LED on lab_pc); `op`: what the operator presses
/// besides the lab button. Each firmware step is the longest pass of its
/// kind (docs/timing.md §9, "The bound per kind of pass"), the frames each
/// Arduino takes into the passes the path waits for are counted once
/// ("Frames on the path", frames_on_path). Only the
/// lab PC talks Modbus (the other stations' passes have no characters).
LabBound lab_bound(Line& line, bool remote, const LabOperator& op = LabOperator());

/// Bound of seed 000 §11's simpler alternative on `line`: button and LED on
/// lab_remote, the control process on lab_pc's Arduino (no PC, no serial
/// traffic in its passes): timing::arduino_control_latency over the same
/// CAN hops as the Modbus + CANopen path.
LabBound arduino_control_bound(Line& line);

/// The CAN message set of `line` as commissioned (every Arduino powered on:
/// the dictionaries are read from the running gateways), in priority order: every
/// enabled TPDO (event types: period = inhibit time, else the application's
/// rate; synchronous types 0..240: the SYNC period × n, left out when no
/// station produces SYNC), every heartbeat, and the producer's SYNC
/// (1005h bit 30, period 1006h), each with queuing jitter `jitter_us`.
/// Fails when an event TPDO has no known rate.
Status line_can_messages(Line& line, uint32_t jitter_us, std::vector<timing::MessageSpec>* out);

/// Inhibit time (µs) of the enabled TPDO with `cob_id` on the line; 0: none.
uint32_t tpdo_inhibit_us(Line& line, uint32_t cob_id);

/// One CAN hop from the analysis: best = the bare frame until its reception,
/// worst = its response time R, frame_worst = C (so R − C is its queueing).
struct HopTimes {
  uint64_t best_ns = 0;
  uint64_t worst_ns = 0;
  uint64_t frame_worst_ns = 0;
};
/// Analyses message `id` of `messages` (priority order) with its own jitter
/// 0 (the wait for the pass that queues it is a term of its own) at
/// `bitrate_bps`. False when the set has no such message or its response
/// time is unbounded.
bool hop_times(const std::vector<timing::MessageSpec>& messages, uint32_t id, uint32_t bitrate_bps,
               HopTimes* out);

/// Minimum inter-arrival time (µs) the analysis uses for an event-driven
/// TPDO without inhibit time, from what it maps: buttons change no faster
/// than the debounce time, the lab LED no faster than the PC writes it.
uint32_t application_interarrival_us(const LineConfig& c, uint32_t first_mapped_entry);

}  // namespace sim
}  // namespace mb2co
