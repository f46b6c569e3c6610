#include "bridge_options.h"

namespace mb2co {
namespace bridge {

const char* bridge_usage_head() {
  return "usage: mb2co-bridge --serial PATH|--pty LINK [options]\n"
         "Smart bridge (seed 003 §3.2.8) between a serial CANopen segment and SocketCAN: the\n"
         "serial nodes appear on CAN at node id + offset; only what the other side consumes\n"
         "crosses. The bridge polls the segment or starts its token ring.\n"
         "  --can IFACE        SocketCAN interface (default vcan0)\n"
         "  --offset N         CAN node id = serial node id + N (default 0)\n"
         "  --forward ID       a further CAN id the serial nodes consume (an RPDO's COB-ID), repeatable\n"
         "  --verbose          forwarding counters on stderr at exit\n"
         "  --help, --version\n";
}

Status parse_bridge_options(int argc, const char* const* argv, BridgeOptions* o) {
  for (int i = 1; i < argc; ++i) {
    bool taken = false;
    Status s = parse_segment_option(argc, argv, &i, &o->segment, &taken);
    if (!s) return s;
    if (taken) continue;
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      o->help = true;
      continue;
    }
    if (a == "--version") {
      o->version = true;
      continue;
    }
    if (a == "--verbose") {
      o->verbose = true;
      continue;
    }
    if (a != "--can" && a != "--offset" && a != "--forward")
      return Status::failure("unknown option " + a + " (try --help)");
    if (i + 1 >= argc) return Status::failure("option " + a + " needs a value (try --help)");
    const char* v = argv[++i];
    long n = 0;
    if (a == "--can") {
      o->can = v;
    } else if (a == "--offset") {
      if (!parse_number(v, 0, 126, &n))
        return Status::failure(std::string("bad --offset '") + v + "' (0..126)");
      o->offset = static_cast<uint8_t>(n);
    } else {
      if (!parse_number(v, 1, 0x7FF, &n))
        return Status::failure(std::string("bad --forward '") + v + "' (a CAN id 1..7FFh)");
      if (o->forward_count == BridgeOptions::kMaxForward)
        return Status::failure("too many --forward (16 at most)");
      o->forward[o->forward_count++] = static_cast<uint16_t>(n);
    }
  }
  return Status::ok();
}

Status bridge_config(const BridgeOptions& o, serialnet::BridgeConfig* out) {
  serialnet::BridgeConfig c = {};
  Status bus = segment_bus_config(
      o.segment, o.segment.token ? serialnet::Access::kTokenStarter : serialnet::Access::kPoller, &c.bus);
  if (!bus) return bus;
  c.bridge_node = o.segment.bridge_node();
  c.node_offset = o.offset;
  c.extra_to_serial = o.forward;
  c.extra_count = o.forward_count;
  if (serialnet::check_bridge_config(c) == serialnet::BridgeConfigError::kOffset)
    return Status::failure("--offset " + std::to_string(o.offset) +
                           " puts the serial nodes beyond CAN node id 127");
  if (serialnet::check_bridge_config(c) != serialnet::BridgeConfigError::kOk)
    return Status::failure("bad segment settings");
  *out = c;
  return Status::ok();
}

}  // namespace bridge
}  // namespace mb2co
