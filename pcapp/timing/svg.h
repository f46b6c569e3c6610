// SVG picture of the worst-case level-i busy period of one message: one row
// per message that takes part (the lower-priority blocker on top), a box for
// every transmission, a tick for every queuing instant, and the response time
// of each instance of the chosen message.
#pragma once
#include <string>
#include <vector>

#include "timing/message_set.h"
#include "timing/rta.h"

namespace mb2co {
namespace timing_cli {

/// `set` and `rta` in priority order (same length), `target` the index of
/// the message to draw, `result` its analysis, at `bitrate_bps` (ticks).
std::string busy_period_svg(const std::vector<timing::MessageSpec>& set,
                            const std::vector<timing::RtaMessage>& rta, size_t target,
                            const timing::RtaResult& result, uint32_t bitrate_bps);

}  // namespace timing_cli
}  // namespace mb2co
