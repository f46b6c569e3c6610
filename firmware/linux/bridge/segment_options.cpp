#include "segment_options.h"

#include <cstdlib>
#include <cstring>

namespace mb2co {
namespace bridge {

const char* segment_usage() {
  return "  --serial PATH      the segment on an existing tty (or a multi-drop hub's pty)\n"
         "  --pty LINK         the segment on a new pseudo-terminal, symlinked at LINK\n"
         "  --baud N           line bit rate (default 115200; the windows are timed by it)\n"
         "  --bits 11|8|7|6    identifier bits of the connection set (default 8)\n"
         "  --access poll|token  bus access: the bridge polls, or starts a token ring (default poll)\n"
         "  --nodes A-B        the serial nodes' ids (default 1-3); the bridge's window is B+1\n"
         "  --window-us W      window per node, µs (default 20000)\n"
         "  --guard-us G       silence before a window ends, µs (default 5000)\n"
         "  --echo             the serial adapter echoes what we send (RS-485): drop it\n";
}

bool parse_number(const char* s, long lo, long hi, long* out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 0);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  *out = v;
  return true;
}

Status parse_segment_option(int argc, const char* const* argv, int* i, SegmentOptions* o, bool* taken) {
  const std::string a = argv[*i];
  *taken = true;
  if (a == "--echo") {
    o->echo = true;
    return Status::ok();
  }
  static const char* const kWithValue[] = {"--serial", "--pty",   "--baud",      "--bits",
                                           "--access", "--nodes", "--window-us", "--guard-us"};
  bool known = false;
  for (const char* k : kWithValue) known = known || a == k;
  if (!known) {
    *taken = false;
    return Status::ok();
  }
  if (*i + 1 >= argc) return Status::failure("option " + a + " needs a value (try --help)");
  const char* v = argv[++*i];
  const std::string bad = "bad " + a + " '" + v + "'";
  long n = 0;
  if (a == "--serial") {
    o->serial = v;
  } else if (a == "--pty") {
    o->pty_link = v;
  } else if (a == "--baud") {
    if (!parse_number(v, 1200, 4000000, &n)) return Status::failure(bad);
    o->baud = static_cast<uint32_t>(n);
  } else if (a == "--bits") {
    if (!parse_number(v, 6, 11, &n) || (n != 11 && n != 8 && n != 7 && n != 6))
      return Status::failure(bad + " (11, 8, 7 or 6)");
    o->bits = static_cast<uint8_t>(n);
  } else if (a == "--access") {
    if (std::strcmp(v, "poll") != 0 && std::strcmp(v, "token") != 0)
      return Status::failure(bad + " (poll or token)");
    o->token = std::strcmp(v, "token") == 0;
  } else if (a == "--nodes") {
    long first = 0;
    long last = 0;
    const char* dash = std::strchr(v, '-');
    const std::string left = dash ? std::string(v, dash) : std::string();
    if (dash == nullptr || !parse_number(left.c_str(), 1, 126, &first) ||
        !parse_number(dash + 1, 1, 126, &last) || first > last) {
      return Status::failure(bad + " (A-B, 1 <= A <= B)");
    }
    o->first = static_cast<uint8_t>(first);
    o->last = static_cast<uint8_t>(last);
  } else if (a == "--window-us") {
    if (!parse_number(v, 100, 10000000, &n)) return Status::failure(bad + " (100..10000000)");
    o->window_us = static_cast<uint32_t>(n);
  } else if (a == "--guard-us") {
    if (!parse_number(v, 0, 10000000, &n)) return Status::failure(bad);
    o->guard_us = static_cast<uint32_t>(n);
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
