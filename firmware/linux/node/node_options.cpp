#include "node_options.h"

#include <cstdlib>
#include <cstring>

namespace mb2co {
namespace node {

const char* usage() {
  return "usage: mb2co-node [options]\n"
         "The gateway firmware on Linux: CANopen node on SocketCAN, Modbus/RTU slave on a\n"
         "serial line, RUN/STOP2 line application; buttons and LEDs on stdin/stdout.\n"
         "  --can IFACE        SocketCAN interface (default vcan0), or 'none'\n"
         "  --pty PATH         create a pseudo-terminal and a symlink to it at PATH\n"
         "  --serial DEV       use an existing tty instead of a pty\n"
         "  --baud N           serial baud rate (default 115200)\n"
         "  --parity N|E|O     serial parity (default N)\n"
         "  --node-id N        node id 1..127 when no saved parameters (default 1)\n"
         "  --bitrate K        CAN bit rate kbit/s: 125, 250, 500, 1000\n"
         "  --stations N       stations in the line 2..127 (default 4)\n"
         "  --topology ring|chain\n"
         "  --eeprom FILE      file holding saved parameters (1010h), like the Uno's EEPROM\n"
         "  --help, --version\n"
         "SDO: block and segmented transfers; 1F50h/1 is a DOMAIN of up to 1 MiB in RAM (at\n"
         "start 131072 bytes, byte i = i mod 251) for trying large transfers (README.md).\n"
         "Control (stdin, one command per line): press B | release B | click B [ms] (B: START,\n"
         "STOP, STOP2) | leds? | state? | counters? | quit. Replies, LED and state changes go to\n"
         "stdout (docs/mb2co-node.md). Exit: 0 on SIGINT/SIGTERM/quit, 2 bad option, 1 error.\n";
}

namespace {
bool number(const char* s, long lo, long hi, long* out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}
}  // namespace

Status parse_options(int argc, const char* const* argv, NodeOptions* o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      o->help = true;
      continue;
    }
    if (a == "--version") {
      o->version = true;
      continue;
    }
    static const char* const kWithValue[] = {"--can",      "--pty",     "--serial",  "--eeprom",
                                             "--baud",     "--parity",  "--node-id", "--bitrate",
                                             "--stations", "--topology"};
    bool known = false;
    for (const char* k : kWithValue) known = known || a == k;
    if (!known) return Status::failure("unknown option " + a + " (try --help)");
    if (i + 1 >= argc) return Status::failure("option " + a + " needs a value (try --help)");
    const char* v = argv[++i];
    long n = 0;
    if (a == "--can") {
      o->can = v;
    } else if (a == "--pty") {
      o->pty_link = v;
    } else if (a == "--serial") {
      o->serial = v;
    } else if (a == "--eeprom") {
      o->eeprom = v;
    } else if (a == "--baud") {
      if (!number(v, 1200, 4000000, &n)) return Status::failure(std::string("bad --baud '") + v + "'");
      o->baud = static_cast<uint32_t>(n);
    } else if (a == "--parity") {
      if (std::strlen(v) != 1 || std::strchr("NEO", v[0]) == nullptr) {
        return Status::failure(std::string("bad --parity '") + v + "' (N, E or O)");
      }
      o->parity = v[0];
    } else if (a == "--node-id") {
      if (!number(v, 1, 127, &n)) return Status::failure(std::string("bad --node-id '") + v + "' (1..127)");
      o->node_id = static_cast<uint8_t>(n);
    } else if (a == "--bitrate") {
      if (!number(v, 125, 1000, &n) || (n != 125 && n != 250 && n != 500 && n != 1000)) {
        return Status::failure(std::string("bad --bitrate '") + v + "' (125, 250, 500 or 1000)");
      }
      o->bitrate_kbit = static_cast<uint16_t>(n);
    } else if (a == "--stations") {
      if (!number(v, 2, 127, &n)) return Status::failure(std::string("bad --stations '") + v + "' (2..127)");
      o->stations = static_cast<uint8_t>(n);
    } else if (a == "--topology") {
      if (std::strcmp(v, "ring") != 0 && std::strcmp(v, "chain") != 0) {
        return Status::failure(std::string("bad --topology '") + v + "' (ring or chain)");
      }
      o->topology = std::strcmp(v, "ring") == 0 ? 1 : 0;
    }
  }
  if (!o->serial.empty() && !o->pty_link.empty())
    return Status::failure("--pty and --serial exclude each other");
  return Status::ok();
}

}  // namespace node
}  // namespace mb2co
