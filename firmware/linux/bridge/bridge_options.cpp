#include "bridge_options.h"

namespace mb2co {
namespace bridge {

namespace {

cli::Program make_program() {
  cli::Program p;
  p.name = "mb2co-bridge";
  p.description =
      "Smart bridge (seed 003 §3.2.8) between a serial CANopen segment and SocketCAN: the\n"
      "serial nodes appear on CAN at node id + offset; only what the other side consumes\n"
      "crosses. The bridge polls the segment or starts its token ring. The segment needs\n"
      "--serial PATH or --pty LINK.\n";
  cli::Command c;
  c.options = segment_options();
  const std::vector<cli::Option> can_side = {
      cli::text("--can", "IFACE", "SocketCAN interface (default vcan0)"),
      cli::uint_range("--offset", "N", 0, 126, "CAN node id = serial node id + N (default 0)"),
      cli::text("--forward", "ID[,ID]...",
                "further CAN ids the serial nodes consume (an RPDO's COB-ID), 1..7FFh,\n"
                "decimal or 0x hex, 16 at most"),
      cli::flag("--verbose", "forwarding counters on stderr at exit"),
  };
  c.options.insert(c.options.end(), can_side.begin(), can_side.end());
  p.commands = {c};
  p.footer = "\nexit status: 0 on SIGINT/SIGTERM, 1 runtime error, 2 usage error\n";
  return p;
}

}  // namespace

const cli::Program& bridge_program() {
  static const cli::Program p = make_program();
  return p;
}

Status apply_bridge_options(const cli::Args& a, BridgeOptions* o) {
  Status segment = apply_segment_options(a, &o->segment);
  if (!segment) return segment;
  o->can = a.get("--can", o->can);
  o->offset = static_cast<uint8_t>(a.uint("--offset", o->offset));
  o->verbose = a.has("--verbose") || o->verbose;
  if (a.has("--forward")) {
    const std::string list = a.get("--forward");
    o->forward_count = 0;
    for (size_t start = 0; start <= list.size();) {
      size_t comma = list.find(',', start);
      if (comma == std::string::npos) comma = list.size();
      const std::string id = list.substr(start, comma - start);
      long n = 0;
      if (!parse_number(id.c_str(), 1, 0x7FF, &n))
        return Status::failure("--forward must be CAN ids 1..7FFh, got \"" + id + "\"");
      if (o->forward_count == BridgeOptions::kMaxForward) return Status::failure("--forward: 16 ids at most");
      o->forward[o->forward_count++] = static_cast<uint16_t>(n);
      start = comma + 1;
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
