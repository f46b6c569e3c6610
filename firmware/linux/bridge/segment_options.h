// The serial-segment options every Linux program on a CANopen serial segment
// takes (mb2co-bridge, the serial I/O node of tests/bridge), parsed into the
// segment's BusConfig (shared/serialnet/serial_link.h), so that all devices
// of one segment are configured by the same words. The options are entries of
// each program's table of the shared command-line layer (shared/host/cli.h,
// docs/cli.md): bad values are usage errors, exit 2.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/cli.h"
#include "host/status.h"
#include "serialnet/serial_link.h"

namespace mb2co {
namespace bridge {

struct SegmentOptions {
  std::string serial;    ///< --serial PATH: an existing tty (or a hub's pty)
  std::string pty_link;  ///< --pty LINK: a new pty, symlinked at LINK
  uint32_t baud = 115200;
  uint8_t bits = 8;    ///< identifier bits: 11, 8, 7 or 6
  bool token = false;  ///< --access token (default poll)
  uint8_t first = 1;   ///< --nodes A-B: the serial CANopen nodes
  uint8_t last = 3;
  uint32_t window_us = 20000;  ///< W per node: generous, a pty hub adds ms of latency
  uint32_t guard_us = 5000;    ///< G
  bool echo = false;           ///< --echo: the adapter hands back what we send (RS-485)

  /// The bridge's own window: the node id after the last serial node.
  uint8_t bridge_node() const { return static_cast<uint8_t>(last + 1u); }
};

/// The segment options' entries for a program's option table.
std::vector<cli::Option> segment_options();
/// Fills `o` from a parse whose table held segment_options() (options not
/// given keep their value); fails with one line for a value the table cannot
/// check (--nodes A-B).
Status apply_segment_options(const cli::Args& args, SegmentOptions* o);
/// The segment's BusConfig (nodes first..bridge_node, `access` for this
/// device), checked; a failure says which option is wrong.
Status segment_bus_config(const SegmentOptions& o, serialnet::Access access, serialnet::BusConfig* out);
/// Whole number in [lo, hi], decimal or 0x hex.
bool parse_number(const char* s, long lo, long hi, long* out);

}  // namespace bridge
}  // namespace mb2co
