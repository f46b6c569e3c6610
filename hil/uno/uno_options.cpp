#include "uno_options.h"

#include <stdlib.h>

#include <cmath>

namespace mb2co {
namespace uno {

const char* usage() {
  return "usage: mb2co-uno [options]\n"
         "The Uno's gateway image (mb2co-gateway.elf) in libsimavr: ATmega328P at 16 MHz paced\n"
         "to real time, USART0 on a pty, the MCP2515 shield on SocketCAN, buttons and LEDs on\n"
         "stdin/stdout (docs/uno-sim.md).\n"
         "  --elf FILE         the AVR image (default: the one this build tree made)\n"
         "  --can IFACE        SocketCAN interface (default vcan0), or 'none'\n"
         "  --pty PATH         symlink to the pty at PATH (removed at exit)\n"
         "  --eeprom FILE      1 KiB EEPROM image: loaded at start, written back at exit\n"
         "  --duration S       stop after S simulated seconds (0.001..86400)\n"
         "  --unpaced          run as fast as simavr can, not at real time (measurements)\n"
         "  --trace-can        print 'can ID#DATA sim_us=T at_us=T' for every frame the chip sends\n"
         "  --help, --version\n"
         "Control (stdin, one command per line): press B | release B | click B [ms] (B: START,\n"
         "STOP, STOP2) | leds? | stack? | quit. Exit: 0 on SIGINT/SIGTERM/quit, 2 bad option, 1 error.\n";
}

Status parse_options(int argc, const char* const* argv, UnoOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      o->help = true;
    } else if (a == "--version") {
      o->version = true;
    } else if (a == "--unpaced") {
      o->unpaced = true;
    } else if (a == "--trace-can") {
      o->trace_can = true;
    } else if (a == "--elf" || a == "--can" || a == "--pty" || a == "--eeprom" || a == "--duration") {
      if (i + 1 >= argc) return Status::failure("option " + a + " needs a value (try --help)");
      const std::string v = argv[++i];
      if (v.empty()) return Status::failure("option " + a + " needs a value (try --help)");
      if (a == "--elf") o->elf = v;
      if (a == "--can") o->can = v;
      if (a == "--pty") o->pty_link = v;
      if (a == "--eeprom") o->eeprom = v;
      if (a == "--duration") {
        char* end = nullptr;
        const double s = strtod(v.c_str(), &end);
        if (end == v.c_str() || *end != '\0' || !(s >= 0.001 && s <= 86400.0)) {
          return Status::failure("bad --duration '" + v + "' (seconds, 0.001..86400)");
        }
        o->duration_ms = static_cast<uint32_t>(std::llround(s * 1000.0));
      }
    } else if (a == "--serial" || a == "--baud" || a == "--parity" || a == "--node-id" || a == "--bitrate" ||
               a == "--stations" || a == "--topology") {
      return Status::failure("option " + a +
                             " is mb2co-node's: the Uno image keeps its settings in its EEPROM (--eeprom)");
    } else {
      return Status::failure("unknown option " + a + " (try --help)");
    }
  }
  return Status::ok();
}

}  // namespace uno
}  // namespace mb2co
