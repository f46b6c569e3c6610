// Joins the line's CAN analysis to the latency bound: the CAN hops of the
// Modbus + CANopen path are the TPDO1s of the button's node (up) and of the
// PC's node (down), with the worst case from the revised analysis of the
// whole line and the best case from the bare frame.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "timing/latency.h"
#include "timing/line_config.h"

namespace mb2co {
namespace timing {

/// Caller-owned working memory for one line analysis: each array holds
/// `capacity` ≥ line_message_count(cfg) entries.
struct LineScratch {
  MessageSpec* specs;
  RtaMessage* rta;
  RtaResult* results;
  size_t capacity;
};

enum class HopStatus : uint8_t {
  kOk,
  kLine,       ///< the configuration is invalid (see *line_status)
  kNoTpdo1,    ///< the line has no TPDO1 to carry button and LED
  kNode,       ///< a node outside 1..stations, or both nodes the same
  kUnbounded,  ///< a TPDO1 has no bounded response time on this line
};

/// Fills p->can_* for a button/LED on `button_node` and the PC on `pc_node`.
HopStatus fill_can_hops(const LineCanConfig& cfg, WorstCase convention, uint8_t button_node, uint8_t pc_node,
                        const LineScratch& scratch, LatencyParams* p, LineStatus* line_status);

}  // namespace timing
}  // namespace mb2co
