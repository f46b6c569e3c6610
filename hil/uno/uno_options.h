// Command line of mb2co-uno (docs/cli.md, shared/host/cli.h): bad input gives
// one line and exit 2.
#pragma once
#include <stdint.h>

#include <string>

#include "host/cli.h"

namespace mb2co {
namespace uno {

struct UnoOptions {
  std::string image = "gateway";  ///< --image: which image (uno_image.h) and wiring
  std::string elf;                ///< the AVR image file; empty: the build's file of `image`
  std::string can = "vcan0";      ///< SocketCAN interface, or "none": frames sent are dropped
  std::string pty_link;           ///< --pty PATH: symlink to the pty made for USART0
  std::string eeprom;             ///< 1 KiB file: the EEPROM at start, written back at exit
  uint32_t duration_ms = 0;       ///< --duration S: stop after S simulated seconds (0: run on)
  bool unpaced = false;           ///< --unpaced: as fast as simavr can (measurements)
  bool trace_can = false;         ///< --trace-can: a "can" line per frame the chip sends
  bool stats = false;             ///< --stats: the loop's system calls at exit (io_counts.h)
};

/// The option table of mb2co-uno (help, parser and completion come from it).
const cli::Program& program();
/// Fills `out` from a parse of program() (fields not given keep their value).
void apply_options(const cli::Args& args, UnoOptions* out);

}  // namespace uno
}  // namespace mb2co
