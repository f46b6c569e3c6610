// Command line of mb2co-bridge (the convention of docs/cli.md,
// shared/host/cli.h): the segment options (segment_options.h) and the CAN
// side in one option table. Apart from main so that tests can call it; bad
// input is one line and exit 2.
#pragma once
#include <stdint.h>

#include <string>

#include "host/cli.h"
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
  uint16_t forward[kMaxForward] = {};  ///< --forward ID[,ID]...: extra CAN ids the serial nodes consume
  uint8_t forward_count = 0;
  bool verbose = false;  ///< counters on stderr at exit
};

/// The option table of mb2co-bridge (help, parser and completion come from it).
const cli::Program& bridge_program();
/// Fills `out` from a parse of bridge_program(); fails with one line for a
/// value the table cannot check (--nodes, --forward).
Status apply_bridge_options(const cli::Args& args, BridgeOptions* out);
/// The bridge's configuration (`forward` of `o` referenced, not copied), checked.
Status bridge_config(const BridgeOptions& o, serialnet::BridgeConfig* out);

}  // namespace bridge
}  // namespace mb2co
