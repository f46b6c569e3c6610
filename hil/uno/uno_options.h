// Command line of mb2co-uno. Parsing is apart from main so that bad input
// gives one line and exit 2, and tests can call it directly.
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"

namespace mb2co {
namespace uno {

struct UnoOptions {
  std::string elf;            ///< the AVR image; main fills in the build's default
  std::string can = "vcan0";  ///< SocketCAN interface, or "none": frames sent are dropped
  std::string pty_link;       ///< --pty PATH: symlink to the pty made for USART0
  std::string eeprom;         ///< 1 KiB file: the EEPROM at start, written back at exit
  uint32_t duration_ms = 0;   ///< --duration S: stop after S simulated seconds (0: run on)
  bool unpaced = false;       ///< --unpaced: as fast as simavr can (measurements)
  bool trace_can = false;     ///< --trace-can: a "can" line per frame the chip sends
  bool help = false;
  bool version = false;
};

/// Parses argv; a failure says why in one line.
Status parse_options(int argc, const char* const* argv, UnoOptions* out);
const char* usage();

}  // namespace uno
}  // namespace mb2co
