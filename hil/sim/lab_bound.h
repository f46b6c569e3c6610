// The analytical button-to-LED bound (shared/timing, seed 000 §2.9–2.13, §11)
// for exactly the line being simulated: CAN message set read from the
// commissioned Object Dictionaries (every enabled TPDO and heartbeat), the
// firmware loop from the node timing model, the PC cycle with its jitter.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

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
  SimNs step_ns = 0;                          ///< event → end of the pass that handles it (fw_loop)
};

/// Longest time from an outside event to the end of the pass that handles
/// it, for passes of at most `pass_max_ns`: one pass in progress (or one
/// loop period) plus the handling pass.
SimNs firmware_step_ns(const NodeTiming& t, SimNs pass_max_ns);

/// Bound for the lab of `line` (config().lab_pc / lab_remote set):
/// `remote` = Modbus + CANopen path (button and LED on lab_remote), else
/// Modbus only (button and LED on lab_pc).
LabBound lab_bound(Line& line, bool remote);

/// Minimum inter-arrival time (µs) the analysis uses for an event-driven
/// TPDO without inhibit time, from what it maps: buttons change no faster
/// than the debounce time, the lab LED no faster than the PC writes it.
uint32_t application_interarrival_us(const LineConfig& c, uint32_t first_mapped_entry);

}  // namespace sim
}  // namespace mb2co
