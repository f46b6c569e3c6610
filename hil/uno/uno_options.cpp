#include "uno_options.h"

#include "uno_image.h"

namespace mb2co {
namespace uno {
namespace {

cli::Program make_program() {
  const char* const kNodes = "is mb2co-node's: the Uno image keeps its settings in its EEPROM (--eeprom)";
  cli::Program p;
  p.name = "mb2co-uno";
  p.description =
      "The Uno's gateway image (mb2co-gateway.elf, or another: --image) in libsimavr:\n"
      "ATmega328P at 16 MHz paced to real time, USART0 on a pty, the MCP2515 shield on\n"
      "SocketCAN, buttons and LEDs on stdin/stdout (docs/uno-sim.md).\n";
  cli::Command c;
  c.options = {
      cli::choice("--image", {"gateway", "network", "ionode", "echo"},
                  "which image and board wiring (default gateway; network: the gateway with\n"
                  "FC 2Bh/0Dh on the same wiring; ionode: joystick and LEDs D7, D8)"),
      cli::file("--elf", "FILE", "the AVR image file (default: --image's, made by this build tree)"),
      cli::text("--can", "IFACE", "SocketCAN interface (default vcan0), or 'none'"),
      cli::file("--pty", "PATH", "symlink to the pty at PATH (removed at exit)"),
      cli::file("--eeprom", "FILE", "1 KiB EEPROM image: loaded at start, written back at exit"),
      cli::duration("--duration", 1, 86400000, "stop after T simulated (seconds, or 250ms, 2min)"),
      cli::flag("--unpaced", "run as fast as simavr can, not at real time (measurements)"),
      cli::flag("--trace-can", "print 'can ID#DATA sim_us=T at_us=T' for every frame the chip sends"),
      cli::flag("--stats", "at exit, the loop's system calls by kind and per simulated second (stderr)"),
  };
  for (const char* name :
       {"--serial", "--baud", "--parity", "--node-id", "--bitrate", "--stations", "--topology"}) {
    c.options.push_back(cli::refused(name, kNodes));
  }
  p.commands = {c};
  p.footer =
      "\nControl (stdin, one command per line): press B | release B | click B [ms] (B: START,\n"
      "STOP, STOP2; --image ionode: UP, DOWN, LEFT, RIGHT, CLICK) | leds? | stack? | bus? | help |\n"
      "quit. bus?: frames from the bus the wire carried, those the chip dropped (its filters or\n"
      "full receive buffers), those lost to full buffers alone (overflowed), the wire's busy time.\n"
      "exit status: 0 on SIGINT/SIGTERM/quit, 1 runtime error, 2 usage error\n";
  return p;
}

}  // namespace

const cli::Program& program() {
  static const cli::Program p = make_program();
  return p;
}

void apply_options(const cli::Args& a, UnoOptions* o) {
  o->image = a.get("--image", o->image);
  o->elf = a.get("--elf", o->elf);
  o->can = a.get("--can", o->can);
  o->pty_link = a.get("--pty", o->pty_link);
  o->eeprom = a.get("--eeprom", o->eeprom);
  o->duration_ms = static_cast<uint32_t>(a.duration_ms("--duration", o->duration_ms));
  o->unpaced = a.has("--unpaced");
  o->trace_can = a.has("--trace-can");
  o->stats = a.has("--stats");
}

}  // namespace uno
}  // namespace mb2co
