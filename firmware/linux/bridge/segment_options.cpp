#include "segment_options.h"

#include <cstdlib>

namespace mb2co {
namespace bridge {

std::vector<cli::Option> segment_options() {
  return {
      cli::file("--serial", "PATH", "the segment on an existing tty (or a multi-drop hub's pty)"),
      cli::file("--pty", "LINK", "the segment on a new pseudo-terminal, symlinked at LINK"),
      cli::uint_range("--baud", "N", 1200, 4000000,
                      "line bit rate 1200..4000000 (default 115200; the windows are timed by it)"),
      cli::choice("--bits", {"11", "8", "7", "6"}, "identifier bits of the connection set (default 8)"),
      cli::choice("--access", {"poll", "token"},
                  "bus access: the bridge polls, or starts a token ring (default poll)"),
      cli::text("--nodes", "A-B",
                "the serial nodes' ids, 1 <= A <= B (default 1-3); the bridge's window is B+1"),
      cli::uint_range("--window-us", "W", 100, 10000000, "window per node, µs (default 20000)"),
      cli::uint_range("--guard-us", "G", 0, 10000000, "silence before a window ends, µs (default 5000)"),
      cli::flag("--echo", "the serial adapter echoes what we send (RS-485): drop it"),
  };
}

bool parse_number(const char* s, long lo, long hi, long* out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 0);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}

Status apply_segment_options(const cli::Args& a, SegmentOptions* o) {
  o->serial = a.get("--serial", o->serial);
  o->pty_link = a.get("--pty", o->pty_link);
  o->baud = static_cast<uint32_t>(a.uint("--baud", o->baud));
  o->bits = static_cast<uint8_t>(a.uint("--bits", o->bits));
  if (a.has("--access")) o->token = a.get("--access") == "token";
  o->window_us = static_cast<uint32_t>(a.uint("--window-us", o->window_us));
  o->guard_us = static_cast<uint32_t>(a.uint("--guard-us", o->guard_us));
  o->echo = a.has("--echo") || o->echo;
  if (a.has("--nodes")) {
    const std::string v = a.get("--nodes");
    const size_t dash = v.find('-');
    long first = 0;
    long last = 0;
    if (dash == std::string::npos || !parse_number(v.substr(0, dash).c_str(), 1, 126, &first) ||
        !parse_number(v.c_str() + dash + 1, 1, 126, &last) || first > last) {
      return Status::failure("--nodes must be A-B, 1 <= A <= B <= 126, got \"" + v + "\"");
    }
    o->first = static_cast<uint8_t>(first);
    o->last = static_cast<uint8_t>(last);
  }
  return Status::ok();
}

Status segment_bus_config(const SegmentOptions& o, serialnet::Access access, serialnet::BusConfig* out) {
  if (!o.serial.empty() && !o.pty_link.empty())
    return Status::failure("--pty and --serial exclude each other");
  if (o.serial.empty() && o.pty_link.empty())
    return Status::failure("the segment needs --serial PATH or --pty LINK");
  serialnet::BusConfig c = {};
  c.set = serialnet::connection_set(static_cast<serialnet::IdBits>(o.bits));
  c.baud = o.baud;
  c.access = access;
  c.first_node = o.first;
  c.last_node = o.bridge_node();
  c.window_us = o.window_us;
  c.guard_us = o.guard_us;
  switch (serialnet::check_config(c)) {
    case serialnet::ConfigError::kOk:
      break;
    case serialnet::ConfigError::kBaud:
      return Status::failure("bad --baud");
    case serialnet::ConfigError::kNodeRange:
      return Status::failure("--nodes " + std::to_string(o.first) + "-" + std::to_string(o.last) +
                             " and the bridge's window " + std::to_string(o.bridge_node()) + " exceed the " +
                             std::to_string(o.bits) + "-bit set's " + std::to_string(c.set.max_nodes) +
                             " nodes");
    case serialnet::ConfigError::kWindowTooShort:
      return Status::failure("--window-us less --guard-us holds no longest message at this --baud");
  }
  *out = c;
  return Status::ok();
}

}  // namespace bridge
}  // namespace mb2co
