#include "cli_options.h"

#include <stdlib.h>

#include <algorithm>

namespace mb2co {
namespace master {

const char* usage_text() {
  return "usage: mb2co-master [-i IFACE | --via-modbus PORT[:SLAVE] [--baud N]] [-t TIMEOUT_MS] [--heartbeat "
         "MS]\n"
         "                    [--json] [--eds FILE] COMMAND ...\n"
         "  --via-modbus: SDO and NMT through an mb2co gateway on a serial port (FC 2Bh/0Dh), no CAN\n"
         "  interface needed: scan read write upload download nmt dump configure (no block transfer)\n"
         "  -t MS: SDO timeout (default 1000); --heartbeat MS: end the transfers of a node whose\n"
         "  heartbeats stop for MS (the watchdog); NODE may be a list: 2,3,5-7; INDEX is hexadecimal\n"
         "  (1018, 0x1018, 1018h), SUB and NODE decimal unless 0x...\n"
         "  scan [FIRST [LAST]]                      node ids that answer, with 1000h, 1018h, 1008h\n"
         "  read NODE INDEX SUB [TYPE]               SDO upload, shown as TYPE (or as --eds says)\n"
         "  write NODE INDEX SUB [TYPE] VALUE        SDO download\n"
         "  upload NODE INDEX SUB FILE [--block]     an object into a file, with progress\n"
         "  download NODE INDEX SUB FILE [--block]   a file into an object, with progress\n"
         "  nmt start|stop|preop|reset|reset-comm NODE|all\n"
         "  sync [--period MS] [--count N] [--overflow N] [--cob-id ID]\n"
         "  dump NODE [FILE.dcf]                     the whole OD (as --eds lists it) uploaded, as a DCF\n"
         "  configure NETWORK_FILE [--save] [--no-start] [--one-at-a-time]   DCFs written, then started\n"
         "  watch [--nodes LIST] [--heartbeat MS | --guard MS [--life N]] [--for S] [--raw]\n"
         "                                           NMT state, lost/back, EMCY, PDOs decoded\n"
         "TYPE: u8 u16 u32 u64 i8 i16 i32 i64 r32 r64 vs (string) os (hex bytes) d (domain, hex)\n"
         "exit: 0 done, 1 refused (SDO abort), 2 usage or file error, 3 CAN interface, 4 no answer\n";
}

Status parse_number(const std::string& text, uint64_t max, const char* what, uint64_t* value) {
  std::string t = text;
  int base = 10;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t = t.substr(2);
    base = 16;
  } else if (t.size() > 1 && (t.back() == 'h' || t.back() == 'H')) {
    t.pop_back();
    base = 16;
  }
  const bool digits = !t.empty() && std::all_of(t.begin(), t.end(), [base](char c) {
    return base == 16 ? isxdigit(static_cast<unsigned char>(c)) != 0 : (c >= '0' && c <= '9');
  });
  if (!digits || t.size() > 20) return Status::failure(std::string("bad ") + what + " '" + text + "'");
  errno = 0;
  const unsigned long long v = strtoull(t.c_str(), nullptr, base);
  if (errno != 0 || v > max)
    return Status::failure(std::string(what) + " '" + text + "' out of range (at most " +
                           std::to_string(max) + ")");
  *value = v;
  return Status::ok();
}

Status parse_node_id(const std::string& text, bool allow_all, uint8_t* node_id) {
  if (allow_all && (text == "all" || text == "0")) {
    *node_id = 0;
    return Status::ok();
  }
  uint64_t v = 0;
  Status s = parse_number(text, 127, "node id", &v);
  if (!s) return s;
  if (v == 0)
    return Status::failure("node id 0: node ids are 1..127" + std::string(allow_all ? " or all" : ""));
  *node_id = static_cast<uint8_t>(v);
  return Status::ok();
}

Status parse_node_list(const std::string& text, std::vector<uint8_t>* nodes) {
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string part =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const size_t dash = part.find('-');
    uint8_t a = 0, b = 0;
    Status s = parse_node_id(part.substr(0, dash), false, &a);
    if (s && dash != std::string::npos) s = parse_node_id(part.substr(dash + 1), false, &b);
    if (!s) return s;
    if (dash == std::string::npos) b = a;
    if (b < a) return Status::failure("node range '" + part + "' runs backwards");
    for (int id = a; id <= b; ++id) nodes->push_back(static_cast<uint8_t>(id));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Status::ok();
}

Status parse_index_sub(const std::string& index, const std::string& sub, uint16_t* i, uint8_t* s) {
  // An index is hexadecimal in every CANopen text (1018h): "1018", "0x1018"
  // and "1018h" are the same object.
  uint64_t v = 0;
  const bool marked = index.rfind("0x", 0) == 0 || index.rfind("0X", 0) == 0 ||
                      (!index.empty() && (index.back() == 'h' || index.back() == 'H'));
  Status st = parse_number(marked ? index : "0x" + index, 0xFFFF, "index", &v);
  if (!st) return Status::failure("bad index '" + index + "' (hexadecimal, 0000..FFFF)");
  *i = static_cast<uint16_t>(v);
  st = parse_number(sub, 0xFF, "sub-index", &v);
  if (!st) return st;
  *s = static_cast<uint8_t>(v);
  return Status::ok();
}

bool take_option(std::vector<std::string>* words, const std::string& name, bool flag, std::string* value) {
  for (size_t i = 0; i < words->size(); ++i) {
    if ((*words)[i] != name) continue;
    if (flag) {
      words->erase(words->begin() + static_cast<long>(i));
      return true;
    }
    if (i + 1 >= words->size()) return false;
    if (value) *value = (*words)[i + 1];
    words->erase(words->begin() + static_cast<long>(i), words->begin() + static_cast<long>(i) + 2);
    return true;
  }
  return false;
}

namespace {

/// "PORT" or "PORT:SLAVE" (1..247); a colon followed by something that is
/// not a number stays part of the path.
Status parse_gateway(const std::string& text, Options* out) {
  const size_t colon = text.rfind(':');
  std::string port = text;
  if (colon != std::string::npos && colon + 1 < text.size() &&
      std::all_of(text.begin() + static_cast<long>(colon) + 1, text.end(),
                  [](char c) { return isdigit(c); })) {
    uint64_t slave = 0;
    Status s = parse_number(text.substr(colon + 1), 247, "Modbus slave address", &slave);
    if (!s) return s;
    if (slave == 0) return Status::failure("Modbus slave address 0 is the broadcast: a gateway is 1..247");
    out->gateway_slave = static_cast<uint8_t>(slave);
    port = text.substr(0, colon);
  }
  if (port.empty()) return Status::failure("--via-modbus wants PORT[:SLAVE]");
  out->gateway_port = port;
  return Status::ok();
}

}  // namespace

std::string needs_can_frames(const std::string& what) {
  return what + " needs raw CAN frames: not through a gateway (--via-modbus), use -i IFACE";
}

std::string via_modbus_refusal(const Options& o) {
  if (o.gateway_port.empty()) return std::string();
  if (o.command == "watch" || o.command == "sync") return needs_can_frames(o.command);
  if (o.heartbeat_ms) return needs_can_frames("--heartbeat (the watchdog listens to heartbeats)");
  const bool block = std::find(o.words.begin(), o.words.end(), "--block") != o.words.end();
  if ((o.command == "upload" || o.command == "download") && block)
    return needs_can_frames(o.command + " --block (block transfer)");
  return std::string();
}

Status parse_options(int argc, char** argv, Options* out) {
  int i = 1;
  for (; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.empty() || a[0] != '-') break;
    auto value = [&](std::string* v) {
      if (i + 1 >= argc) return Status::failure("option " + a + " needs a value");
      *v = argv[++i];
      return Status::ok();
    };
    std::string v;
    if (a == "-i" || a == "--interface") {
      Status s = value(&out->iface);
      if (!s) return s;
    } else if (a == "-t" || a == "--timeout") {
      Status s = value(&v);
      if (!s) return s;
      uint64_t ms = 0;
      s = parse_number(v, 600000, "timeout", &ms);
      if (!s) return s;
      if (ms == 0) return Status::failure("timeout 0: the SDO timeout is 1..600000 ms");
      out->timeout_ms = static_cast<uint32_t>(ms);
    } else if (a == "--heartbeat") {
      Status s = value(&v);
      if (!s) return s;
      uint64_t ms = 0;
      s = parse_number(v, 65535, "heartbeat consumer time", &ms);
      if (!s) return s;
      out->heartbeat_ms = static_cast<uint16_t>(ms);
    } else if (a == "--via-modbus") {
      Status s = value(&v);
      if (!s) return s;
      s = parse_gateway(v, out);
      if (!s) return s;
    } else if (a == "--baud") {
      Status s = value(&v);
      if (!s) return s;
      uint64_t baud = 0;
      s = parse_number(v, 4000000, "baud rate", &baud);
      if (!s) return s;
      if (baud < 1200) return Status::failure("baud rate '" + v + "' below 1200");
      out->baud = static_cast<uint32_t>(baud);
    } else if (a == "--json") {
      out->json = true;
    } else if (a == "--eds") {
      Status s = value(&out->eds);
      if (!s) return s;
    } else if (a == "-h" || a == "--help") {
      out->command = "help";
      return Status::ok();
    } else {
      return Status::failure("unknown option " + a);
    }
  }
  if (i >= argc)
    return Status::failure(
        "no command (scan, read, write, upload, download, nmt, sync, dump, configure, watch)");
  out->command = argv[i++];
  for (; i < argc; ++i) {
    // --json after the command too ("watch --json"): where a user puts it.
    if (std::string(argv[i]) == "--json")
      out->json = true;
    else
      out->words.emplace_back(argv[i]);
  }
  return Status::ok();
}

}  // namespace master
}  // namespace mb2co
