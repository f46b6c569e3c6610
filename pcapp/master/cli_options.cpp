#include "cli_options.h"

#include <ctype.h>

#include <algorithm>

#include "exit_codes.h"
#include "modbus/tcp_framer.h"
#include "value_text.h"

namespace mb2co {
namespace master {

// The master's own exit codes keep the convention's two (docs/cli.md): a
// usage error is 2 like every program's, and 1 is a runtime error (a node
// refused); 3, 4 and 130 only say more.
static_assert(kExitUsage == cli::kExitUsage, "a usage error is 2 in every program");
static_assert(kExitRefused == cli::kExitRuntime, "1 stays a runtime error");

namespace {

cli::Command command(std::string name, std::string summary, std::string operands, size_t min_operands,
                     size_t max_operands, std::vector<cli::Option> options = {}) {
  cli::Command c;
  c.min_operands = min_operands;
  c.name = std::move(name);
  c.summary = std::move(summary);
  c.operands = std::move(operands);
  c.max_operands = max_operands;
  c.options = std::move(options);
  return c;
}

std::vector<cli::Option> sdo_mode_options() {
  return {cli::flag("--block", "CiA 301 block transfer with CRC (not through a gateway)"),
          cli::flag("--segmented", "segmented even when 4 bytes would go expedited")};
}

std::vector<cli::Option> upload_options() {
  std::vector<cli::Option> o = sdo_mode_options();
  o.push_back(cli::uint_range("--max-bytes", "N", 1, 0xFFFFFFFFu,
                              "the most bytes taken: a larger size is refused at once, a\n"
                              "transfer without one stopped there (05040005h sent; default " +
                                  std::to_string(kUploadMaxBytesDefault) + ")"));
  return o;
}

cli::Program make_program() {
  const Options defaults;
  cli::Program p;
  p.name = "mb2co-master";
  p.description =
      "A CANopen master on SocketCAN (docs/mb2co-master.md): SDO transfers to many nodes at once,\n"
      "NMT, SYNC, TIME, a watch of the bus. With --via-modbus, SDO and NMT through an mb2co gateway on a\n"
      "serial port instead (FC 2Bh/0Dh, no CAN interface needed).\n";
  p.commands = {
      command("scan", "node ids that answer, with 1000h, 1018h, 1008h", "[FIRST [LAST]]", 0, 2),
      command("read", "SDO upload, shown as TYPE (or as --eds says)", "NODE INDEX SUB [TYPE]", 3, 4),
      command("write", "SDO download of VALUE (written as read prints it)", "NODE INDEX SUB [TYPE] VALUE", 4,
              5),
      command("upload", "an object into a file, with progress (several nodes: FILE.<node>)",
              "NODE INDEX SUB FILE", 4, 4, upload_options()),
      command("download", "a file into an object, with progress", "NODE INDEX SUB FILE", 4, 4,
              sdo_mode_options()),
      command("nmt", "an NMT command to one node or all", "start|stop|preop|reset|reset-comm NODE|all", 2, 2),
      command("sync", "SYNC frames (with the 1019h counter when --overflow is 2..240)", "", 0, 0,
              {cli::uint_range("--period", "MS", 1, 60000, "one SYNC every MS (needed for --count above 1)"),
               cli::uint_range("--count", "N", 1, 1000000, "SYNCs to send (default 1)"),
               cli::uint_range("--overflow", "N", 0, 240,
                               "counter overflow value, 1019h (default 0: no counter)"),
               cli::text("--cob-id", "ID", "the SYNC's COB-ID, hex as 0x80 or 80h (default 0x80)")}),
      command(
          "time", "TIME frames (CiA 301 TIME_OF_DAY) with the host's clock, UTC", "", 0, 0,
          {cli::uint_range("--period", "MS", 1, 3600000, "one TIME every MS (needed for --count above 1)"),
           cli::uint_range("--count", "N", 1, 1000000, "TIME frames to send (default 1)"),
           cli::text("--cob-id", "ID", "the TIME's COB-ID, 1012h's, hex as 0x100 or 100h (default 0x100)")}),
      command(
          "watch", "NMT state, lost/back, EMCY, PDOs decoded, until Ctrl-C or --for", "", 0, 0,
          {cli::text("--nodes", "LIST", "the node ids to watch: 2,3,5-7 (default 1-127)"),
           cli::uint_range("--heartbeat", "MS", 2, 65535,
                           "heartbeat consumer time: a node silent for MS is lost (default 1000)"),
           cli::uint_range("--guard", "MS", 1, 65535, "node guarding instead: an RTR every MS"),
           cli::uint_range("--life", "N", 1, 255, "with --guard: lost after N unanswered RTRs (default 3)"),
           cli::duration("--for", 1, 2000000, "stop after T (seconds, or 500ms, 2min)"),
           cli::flag("--raw", "only listen: PDOs as bytes, no SDO for the mappings")}),
      command("dump", "the whole OD (as --eds lists it) uploaded, as a DCF (stdout without FILE)",
              "NODE [FILE.dcf]", 1, 2),
      command("configure", "the nodes of a network file written from their DCFs, then started",
              "NETWORK_FILE", 1, 1,
              {cli::flag("--save", "store the parameters (1010h/1 = \"save\")"),
               cli::flag("--no-start", "leave the nodes in their NMT state"),
               cli::flag("--one-at-a-time", "one node after the other, not all at once")}),
      command("serve", "CiA 309-3 (ASCII, as canopend) to many clients on a local or TCP socket", "", 0, 0,
              {cli::text("--listen", "ADDR",
                         "unix:PATH or tcp:[HOST:]PORT (default " + std::string(kServeListenDefault) +
                             "; tcp:PORT\nis 127.0.0.1: no authentication in CiA 309-3, bind where only "
                             "trusted\nprograms reach it)"),
               cli::uint_range("--max-clients", "N", 1, 1024, "connections at once (default 8)"),
               cli::uint_range("--idle-timeout", "MS", 0, 2000000,
                               "close a client silent for MS with nothing pending (default " +
                                   std::to_string(kServeIdleDefaultMs) + "; 0: never)")
                   .with_short('T'),
               cli::uint_range("--heartbeat", "MS", 2, 65535,
                               "heartbeat consumer time: a node silent for MS is told as\n"
                               "\"unknown\" (default 1000)")}),
  };
  p.global_options = {
      cli::text("--interface", "IFACE", "SocketCAN interface (default " + defaults.iface + ")")
          .with_short('i'),
      cli::uint_range("--timeout", "MS", 1, 600000,
                      "SDO timeout: how long a node may take to answer one frame,\n"
                      "and a transfer to make progress (default " +
                          std::to_string(defaults.timeout_ms) + ")")
          .with_short('t'),
      cli::uint_range("--watchdog", "MS", 0, 65535,
                      "end the SDO transfers of a node whose heartbeats stop for MS\n"
                      "(05040000h sent at once, not after -t); default 0: off"),
      cli::flag("--json", "one JSON object per line instead of text"),
      cli::flag("--verbose",
                "one line on stderr: how the CAN socket moves frames\n"
                "(io_uring, or recvmmsg/sendmmsg and why)")
          .with_short('v'),
      cli::file("--eds", "FILE", "the node's EDS: data types for read/write, the entries of dump"),
      cli::file("--via-modbus", "PORT[:SLAVE]|tcp:HOST:PORT",
                "no CAN interface: SDO and NMT through an mb2co gateway on the\n"
                "serial device PORT, Modbus address SLAVE (default 1), or on\n"
                "Modbus/TCP (mb2co-node --tcp; unit id 255)"),
      cli::uint_range(
          "--baud", "N", 1200, 4000000,
          "with --via-modbus: the line's baud rate (default " + std::to_string(defaults.baud) + ")"),
      cli::parity("--parity", "with --via-modbus: the line's parity (default N: 8N1)"),
  };
  p.footer = std::string("\n") +
             "NODE is 1..127 or a list: 2,3,5-7. INDEX is hexadecimal (1018, 0x1018, 1018h); SUB and NODE\n"
             "are decimal unless 0x... TYPE: " +
             type_words() +
             "\n"
             "--watchdog is the SDO commands' heartbeat watchdog (it was --heartbeat); watch --heartbeat\n"
             "and serve --heartbeat are their own consumer times.\n"
             "exit status: 0 done, 1 SDO abort (the node's, or ours: a broken protocol, a size bound),\n"
             "wrong identity, 2 usage error (or a bad file or value), 3 CAN interface (--via-modbus: the\n"
             "port or the gateway; serve: its socket too), 4 no answer (SDO timeout, also no progress;\n"
             "a node lost, nobody answered), 130 interrupted\n";
  return p;
}

/// "PORT" or "PORT:SLAVE" (1..247); a colon followed by something that is
/// not a number stays part of the path.
Status parse_gateway(const std::string& text, Options* out) {
  if (text.rfind("tcp:", 0) == 0) {
    out->gateway_port = text;
    out->gateway_on_tcp = true;
    out->gateway_slave = modbus::kMbapUnitDirect;  // a server addressed by its IP address
    return parse_tcp_address("--via-modbus tcp:", text.substr(4), false, &out->gateway_tcp);
  }
  const size_t colon = text.rfind(':');
  std::string port = text;
  if (colon != std::string::npos && colon + 1 < text.size() &&
      std::all_of(text.begin() + static_cast<long>(colon) + 1, text.end(),
                  [](char c) { return isdigit(static_cast<unsigned char>(c)) != 0; })) {
    uint64_t slave = 0;
    // 0 is the broadcast: a gateway never answers it.
    if (!parse_number(text.substr(colon + 1), 247, "SLAVE", &slave) || slave == 0) {
      return Status::failure("--via-modbus SLAVE must be 1..247, got \"" + text.substr(colon + 1) + "\"");
    }
    out->gateway_slave = static_cast<uint8_t>(slave);
    port = text.substr(0, colon);
  }
  if (port.empty()) return Status::failure("--via-modbus wants PORT[:SLAVE]");
  out->gateway_port = port;
  return Status::ok();
}

}  // namespace

const cli::Program& program() {
  static const cli::Program p = make_program();
  return p;
}

Status apply_options(const cli::Args& a, Options* o) {
  o->iface = a.get("--interface", o->iface);
  o->timeout_ms = static_cast<uint32_t>(a.uint("--timeout", o->timeout_ms));
  o->watchdog_ms = static_cast<uint16_t>(a.uint("--watchdog", o->watchdog_ms));
  o->json = a.has("--json");
  o->verbose = a.has("--verbose");
  o->eds = a.get("--eds", o->eds);
  if (a.has("--via-modbus")) {
    Status s = parse_gateway(a.get("--via-modbus"), o);
    if (!s) return s;
    for (const char* serial : {"--baud", "--parity"}) {
      if (o->gateway_on_tcp && a.has(serial))
        return Status::failure(std::string(serial) + " is the serial line's: not with --via-modbus tcp:");
    }
  } else {
    for (const char* serial : {"--baud", "--parity"}) {
      if (a.has(serial))
        return Status::failure(std::string(serial) + " is the serial line's: only with --via-modbus PORT");
    }
  }
  o->baud = static_cast<uint32_t>(a.uint("--baud", o->baud));
  o->parity = a.parity("--parity", modbus::Parity::kNone);
  o->command = a.command != nullptr ? a.command->name : std::string();
  o->args = a;
  const std::string refusal = via_modbus_refusal(*o);
  return refusal.empty() ? Status::ok() : Status::failure(refusal);
}

std::string needs_can_frames(const std::string& what) {
  return what + " needs raw CAN frames: not through a gateway (--via-modbus), use -i IFACE";
}

std::string via_modbus_refusal(const Options& o) {
  if (o.gateway_port.empty()) return std::string();
  if (o.command == "watch" || o.command == "sync" || o.command == "time") return needs_can_frames(o.command);
  if (o.command == "serve" && o.args.has("--heartbeat"))
    return needs_can_frames("serve --heartbeat (node states come from heartbeats)");
  if (o.watchdog_ms) return needs_can_frames("--watchdog (the watchdog listens to heartbeats)");
  if ((o.command == "upload" || o.command == "download") && o.args.has("--block"))
    return needs_can_frames(o.command + " --block (block transfer)");
  return std::string();
}

}  // namespace master
}  // namespace mb2co
