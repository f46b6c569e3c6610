// Command line of mb2co-node. Parsing is separate from main so that bad
// input gives one line and a non-zero exit, and tests can call it directly.
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"

namespace mb2co {
namespace node {

struct NodeOptions {
  std::string can = "vcan0";  ///< interface name, or "none": Modbus and OD without a bus
  std::string pty_link;       ///< --pty PATH: symlink to the pty we create
  std::string serial;         ///< --serial DEV: an existing tty instead of a pty
  uint32_t baud = 115200;
  char parity = 'N';          ///< N, E or O
  uint8_t node_id = 1;        ///< used when no saved parameters say otherwise
  uint16_t bitrate_kbit = 0;  ///< 0: as stored / default (500)
  uint8_t stations = 0;       ///< 0: as stored / default (4)
  int topology = -1;          ///< -1 as stored, 0 chain, 1 ring
  std::string eeprom;         ///< file backing 1010h "save" (like the Uno's EEPROM)
  bool help = false;
  bool version = false;
};

/// Parses argv; a failure's message is the one line to show.
Status parse_options(int argc, const char* const* argv, NodeOptions* out);
const char* usage();

}  // namespace node
}  // namespace mb2co
