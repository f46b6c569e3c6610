// The two CAN hops of the lab's Modbus + CANopen path bounded together
// (docs/timing.md §9, "The two hops together"): a line-state TPDO (RUN
// state, STOP2 counter) meets at most one of the hops unless the hops are
// less than its inhibit time apart, where the path is short. Internal to
// hil/sim (lab_bound.cpp, lab_window.cpp).
#pragma once
#include <stdint.h>

#include <vector>

#include "sim/line.h"
#include "timing/message_set.h"

namespace mb2co {
namespace sim {

/// True when TPDO `n` (0-based) of station `s` is the line-state TPDO (it
/// maps exactly RUN state 2100h/2 and STOP2 counter 2100h/3) and no RUN
/// state on the line can change (no station has its RUN command 2100h/1
/// set): it is then sent only when a STOP2 press is counted there, or by
/// its event timer.
bool line_state_tpdo_fixed(Line& line, int s, uint16_t n);

/// The hops bounded together, for a window in which every line-state TPDO
/// is sent at most once by its event timer and at most once by the STOP2
/// press the operator makes with the lab press.
struct JointHops {
  bool split = false;    ///< false: no line-state TPDO to split, or the split does not pay
  uint64_t up_ns = 0;    ///< can_up with the worst split (R of the up hop)
  uint64_t down_ns = 0;  ///< can_down with the worst split
  /// Longest time from the up hop's reception to the down PDO's queueing
  /// in which one line-state TPDO can meet both hops (Δ of §9).
  uint64_t close_ns = 0;
  uint32_t split_tpdos = 0;  ///< line-state TPDOs split between the hops
};

/// The worst over every assignment of each line-state TPDO above both hops
/// in priority to one hop of R(up) + R(down) (revised analysis, Davis
/// stuffing, `messages` in priority order as line_can_messages gives them,
/// each hop with its own jitter 0). `span_ns`: the window plus a send's
/// lateness (lab_bound's window); `step_ns`: event → end of the pass that
/// handles it. No split (split false) when a line-state TPDO's event timer could send
/// twice in `span_ns`, or when an analysis is unbounded.
JointHops joint_hops(Line& line, const std::vector<timing::MessageSpec>& messages, uint32_t up_id,
                     uint32_t down_id, uint32_t bitrate_bps, uint64_t span_ns, uint64_t step_ns);

}  // namespace sim
}  // namespace mb2co
