#include "node_options.h"

namespace mb2co {
namespace node {
namespace {

cli::Program make_program() {
  cli::Program p;
  p.name = "mb2co-node";
  p.description =
      "The gateway firmware on Linux: CANopen node on SocketCAN, Modbus/RTU slave on a\n"
      "serial line and/or Modbus/TCP server, RUN/STOP2 line application; buttons and LEDs\n"
      "on stdin/stdout.\n";
  cli::Command c;
  c.options = {
      cli::text("--can", "IFACE", "SocketCAN interface (default vcan0), or 'none'"),
      cli::file("--pty", "PATH", "create a pseudo-terminal and a symlink to it at PATH"),
      cli::file("--serial", "DEV", "use an existing tty instead of a pty; 'none': no serial line"),
      cli::text("--tcp", "HOST:PORT",
                "also serve Modbus/TCP there (a bare PORT: 127.0.0.1; 0.0.0.0:PORT for\n"
                "every interface; port 0: a free one, named in the ready line)"),
      cli::uint_range("--tcp-clients", "N", 1, 32, "Modbus/TCP connections at once 1..32 (default 8)"),
      cli::uint_range("--baud", "N", 1200, 1000000,
                      "serial baud rate 1200..1000000, a standard rate (default 115200)"),
      cli::parity("--parity", "serial parity (default N)"),
      cli::uint_range("--node-id", "N", 1, 127, "node id 1..127 when no saved parameters (default 1)"),
      cli::bitrate_of("--bitrate", cli::can_bitrates(),
                      "CAN bit rate written to 2000h/2: 125k, 250k, 500k or 1M (default as\n"
                      "saved, else 500k); the interface's own rate is set with `ip link`"),
      cli::uint_range("--stations", "N", 2, 127, "stations in the line 2..127 (default as saved, else 4)"),
      cli::choice("--topology", {"ring", "chain"}, "line topology (default as saved, else chain)"),
      cli::file("--eeprom", "FILE", "file holding saved parameters (1010h), like the Uno's EEPROM"),
      cli::uint_range("--eeprom-write-us", "US", 0, 100000,
                      "time to program one byte of --eeprom, in us (default 0; the Uno's\n"
                      "EEPROM: 3300, a first save then takes ~1.5 s, as on the board)"),
      cli::file("--trace-can", "FILE",
                "every CAN frame sent and received, stamped with the host clock:\n"
                "a candump -L log (canplayer, Wireshark), or pcap (LINKTYPE_CAN_SOCKETCAN)\n"
                "when FILE ends in .pcap"),
  };
  p.commands = {c};
  p.footer =
      "\nSDO: block and segmented transfers; 1F50h/1 is a DOMAIN of up to 1 MiB in RAM (at\n"
      "start 131072 bytes, byte i = i mod 251) for trying large transfers (README.md).\n"
      "Control (stdin, one command per line): press B | release B | click B [ms] (B: START,\n"
      "STOP, STOP2) | leds? | state? | counters? | quit. Replies, LED and state changes go to\n"
      "stdout (docs/mb2co-node.md).\n"
      "exit status: 0 on SIGINT/SIGTERM/quit, 1 runtime error, 2 usage error\n";
  return p;
}

}  // namespace

const cli::Program& program() {
  static const cli::Program p = make_program();
  return p;
}

Status apply_options(const cli::Args& a, NodeOptions* o) {
  if (a.has("--pty") && a.has("--serial")) return Status::failure("--pty and --serial exclude each other");
  if (a.get("--trace-can") == "-")
    return Status::failure("--trace-can needs a file: stdout is the control channel");
  o->can = a.get("--can", o->can);
  o->pty_link = a.get("--pty", o->pty_link);
  o->serial = a.get("--serial", o->serial);
  o->baud = static_cast<uint32_t>(a.uint("--baud", o->baud));
  o->parity = a.parity("--parity", o->parity);
  o->node_id = static_cast<uint8_t>(a.uint("--node-id", o->node_id));
  if (a.has("--bitrate")) o->bitrate_kbit = static_cast<uint16_t>(a.bitrate_bps("--bitrate", 0) / 1000u);
  o->stations = static_cast<uint8_t>(a.uint("--stations", o->stations));
  if (a.has("--topology")) o->topology = a.get("--topology") == "ring" ? 1 : 0;
  o->eeprom = a.get("--eeprom", o->eeprom);
  o->eeprom_write_us = static_cast<uint32_t>(a.uint("--eeprom-write-us", o->eeprom_write_us));
  if (a.has("--eeprom-write-us") && o->eeprom.empty())
    return Status::failure("--eeprom-write-us needs --eeprom");
  o->trace_can = a.get("--trace-can", o->trace_can);
  if (a.has("--tcp")) {
    Status where = parse_tcp_address("--tcp", a.get("--tcp"), true, &o->tcp);
    if (!where) return where;
    o->tcp_given = true;
  }
  o->tcp_clients = static_cast<uint32_t>(a.uint("--tcp-clients", o->tcp_clients));
  if (a.has("--tcp-clients") && !o->tcp_given) return Status::failure("--tcp-clients needs --tcp");
  return Status::ok();
}

}  // namespace node
}  // namespace mb2co
