// Command line of mb2co-bridge: the segment options (segment_options.h) and
// the CAN side. Parsed apart from main so that bad input gives one line and
// exit 2, and tests can call it.
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"
#include "segment_options.h"
#include "serialnet/bridge.h"

namespace mb2co {
namespace bridge {

struct BridgeOptions {
  SegmentOptions segment;
  std::string can = "vcan0";
  uint8_t offset = 0;  ///< CAN node id = serial node id + offset
  static const uint8_t kMaxForward = 16;
  uint16_t forward[kMaxForward] = {};  ///< --forward ID: extra CAN ids the serial nodes consume
  uint8_t forward_count = 0;
  bool verbose = false;  ///< counters on stderr at exit
  bool help = false;
  bool version = false;
};

Status parse_bridge_options(int argc, const char* const* argv, BridgeOptions* out);
const char* bridge_usage_head();
/// The bridge's configuration (`forward` of `o` referenced, not copied), checked.
Status bridge_config(const BridgeOptions& o, serialnet::BridgeConfig* out);

}  // namespace bridge
}  // namespace mb2co
