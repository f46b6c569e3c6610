#include "serial_command.h"

#include <algorithm>
#include <string>
#include <vector>

#include "options.h"
#include "report.h"
#include "timing/serial_segment.h"

namespace mb2co {
namespace timing_cli {
namespace {

using serialnet::Access;
using serialnet::BusConfig;

// "4,15,31" → {4, 15, 31}, each within [min, max].
Status uint_list(const Options& o, const char* name, unsigned min, unsigned max, std::vector<unsigned>* out) {
  if (!o.has(name)) return Status::ok();
  out->clear();
  const std::string text = o.get(name);
  size_t from = 0;
  while (from <= text.size()) {
    const size_t comma = std::min(text.find(',', from), text.size());
    const std::string item = text.substr(from, comma - from);
    bool ok = !item.empty() && item.size() <= 6;
    unsigned v = 0;
    for (const char c : item) {
      ok = ok && c >= '0' && c <= '9';
      v = v * 10u + static_cast<unsigned>(c - '0');
    }
    if (!ok || v < min || v > max) {
      return Status::failure(std::string(name) + " must be a list of whole numbers " + std::to_string(min) +
                             ".." + std::to_string(max) + ", got \"" + text + "\"");
    }
    out->push_back(v);
    from = comma + 1;
  }
  return Status::ok();
}

struct Settings {
  BusConfig config = {};
  std::vector<unsigned> nodes{15};
  std::vector<Access> methods{Access::kPolled, Access::kToken};
  std::vector<unsigned> ahead;
  uint8_t dlc = 8;
  uint8_t missing = 0;
  bool bridge = false;
  uint32_t bridge_us = 0;
  uint32_t can_bitrate = 500000;
  Format format = Format::kTable;
};

Status settings(const Options& o, Settings* st) {
  // Values are checked by the parser against serial_command()'s table.
  const cli::Args& args = o.args;
  BusConfig& c = st->config;
  c.set = serialnet::connection_set(static_cast<serialnet::IdBits>(args.uint("--id-bits", 7)));
  Status s = uint_list(o, "--nodes", 1, c.set.max_nodes, &st->nodes);
  if (!s) {
    return Status::failure(s.message() + " (the " + std::to_string(c.set.id_bits) +
                           "-bit set has node ids 1.." + std::to_string(c.set.max_nodes) + ")");
  }
  const std::string access = args.get("--access", "both");
  if (access == "polling") st->methods = {Access::kPolled};
  if (access == "token") st->methods = {Access::kToken};
  c.baud = static_cast<uint32_t>(args.uint("--baud", 115200));
  c.window_us = static_cast<uint32_t>(args.uint("--window-us", 3600));
  c.guard_us = static_cast<uint32_t>(args.uint("--guard-us", 100));
  st->dlc = static_cast<uint8_t>(args.uint("--dlc", 8));
  if (!(s = uint_list(o, "--ahead", 0, 8, &st->ahead))) return s;
  if (st->ahead.size() > 8) return Status::failure("--ahead takes at most 8 messages");
  st->missing = static_cast<uint8_t>(args.uint("--missing", 0));
  st->bridge = args.has("--bridge-us");
  st->bridge_us = static_cast<uint32_t>(args.uint("--bridge-us", 0));
  st->can_bitrate = args.bitrate_bps("--bitrate", 500000);
  c.first_node = 1;
  return format_option(o, &st->format);
}

// The window check of the data link, as a one-line error with the minimum.
Status window_fits(BusConfig c) {
  c.last_node = 1;
  if (serialnet::check_config(c) != serialnet::ConfigError::kWindowTooShort) return Status::ok();
  const bool token = c.access == Access::kToken;
  const uint32_t minimum = c.guard_us + (token ? timing::serial_sync_us(c) : 0u) +
                           serialnet::kMaxEncodedBytes * serialnet::byte_time_us(c.baud);
  return Status::failure("--window-us " + std::to_string(c.window_us) + " holds no longest message" +
                         (token ? " and the pass" : "") + ": at least " + std::to_string(minimum) + " us");
}

Cell latency_cell(const timing::SerialLatency& l, uint32_t us) {
  return l.fits ? Cell::integer(us) : Cell::null();
}

}  // namespace

cli::Command serial_command() {
  return cli::Command{
      "serial",
      "CANopen on a serial segment (seed 003): cycle, token round, worst-case latency",
      "",
      0,
      {cli::text("--nodes", "LIST", "node counts, e.g. 4,15,31 (default 15); at most the set's node ids"),
       cli::choice("--id-bits", {"11", "8", "7", "6"},
                   "connection set: identifier bits (default 7: 15 nodes)"),
       cli::choice("--access", {"polling", "token", "both"}, "bus access (default both)"),
       cli::uint_range("--baud", "N", 1, 10000000, "line bit rate, 8-N-1 (default 115200)"),
       cli::uint_range("--window-us", "US", 1, 100000000, "window W of every node (default 3600)"),
       cli::uint_range("--guard-us", "US", 0, 100000000, "silence G kept before a window ends (default 100)"),
       cli::uint_range("--dlc", "N", 0, 8, "data bytes of the message whose latency is shown (default 8)"),
       cli::text("--ahead", "LIST", "data bytes of higher-priority messages queued with it (default none)"),
       cli::uint_range("--missing", "N", 0, 255,
                       "token passing: ring nodes absent from the segment (default 0)"),
       cli::uint_range("--bridge-us", "US", 0, 100000000,
                       "a bridge forwarding in US: adds the hops to and from CAN"),
       cli::bitrate("--bitrate", 1000, timing::kMaxBitrateBps,
                    "CAN bit rate of the bridge hop (default 500k)"),
       cli::flag("--json", "JSON instead of a table"), cli::flag("--csv", "CSV rows instead of a table")}};
}

int serial_run(const cli::Args& args, std::ostream& out, std::ostream& err) {
  Options o;
  o.args = args;
  Settings st;
  Status s = settings(o, &st);
  for (size_t m = 0; s && m < st.methods.size(); ++m) {
    BusConfig c = st.config;
    c.access = st.methods[m];
    s = window_fits(c);
  }
  if (!s) {
    err << program().name << ": " << s.message() << '\n';
    return cli::kExitUsage;
  }
  std::vector<uint8_t> ahead(st.ahead.begin(), st.ahead.end());
  const uint8_t ahead_count = static_cast<uint8_t>(ahead.size());
  const BusConfig& base = st.config;
  const timing::SerialMessageTime msg = timing::serial_message_time(base.set, base.baud, st.dlc);

  Report r;
  r.columns = {"nodes", "access", "cycle_us", "idle_us", "latency_us", "recover_us"};
  if (st.bridge) {
    r.columns.push_back("to_can_us");
    r.columns.push_back("from_can_us");
  }
  bool refused = false;
  for (const unsigned n : st.nodes) {
    for (const Access a : st.methods) {
      BusConfig c = base;
      c.access = a;
      c.last_node = static_cast<uint8_t>(n);
      const bool token = a == Access::kToken;
      const uint8_t missing = token ? st.missing : uint8_t{0};
      const timing::SerialLatency l =
          timing::serial_latency(c, c.last_node, st.dlc, ahead.data(), ahead_count, missing);
      refused = refused || !l.fits;
      std::vector<Cell> row{Cell::integer(n),
                            Cell::str(token ? "token" : "polling"),
                            Cell::integer(timing::access_cycle_us(c, missing)),
                            Cell::integer(token ? timing::token_round_idle_us(c) : timing::poll_cycle_us(c)),
                            latency_cell(l, l.worst_us),
                            token ? Cell::integer(timing::token_recovery_us(c)) : Cell::null()};
      if (st.bridge) {
        const timing::SerialLatency down =
            timing::can_to_serial(c, c.last_node, st.dlc, ahead.data(), ahead_count, st.bridge_us);
        row.push_back(latency_cell(l, timing::serial_to_can_us(l, st.bridge_us, st.can_bitrate, st.dlc)));
        row.push_back(latency_cell(down, down.worst_us));
      }
      r.rows.push_back(row);
    }
  }
  r.totals = {{"id_bits", Cell::integer(base.set.id_bits)},
              {"baud", Cell::integer(base.baud)},
              {"byte_us", Cell::integer(serialnet::byte_time_us(base.baud))},
              {"window_us", Cell::integer(base.window_us)},
              {"guard_us", Cell::integer(base.guard_us)},
              {"sync_us", Cell::integer(timing::serial_sync_us(base))},
              {"message_bytes", Cell::integer(msg.bytes)},
              {"message_worst_bytes", Cell::integer(msg.bytes_worst)},
              {"message_worst_us", Cell::integer(msg.worst_us)}};
  if (st.bridge) {
    r.totals.push_back({"bridge_us", Cell::integer(st.bridge_us)});
    r.totals.push_back({"can_bitrate", Cell::integer(st.can_bitrate)});
  }
  if (refused) r.notes.push_back("-: the message and those ahead of it do not fit one window (no bound)");
  print_report(r, st.format, out);
  return 0;
}

}  // namespace timing_cli
}  // namespace mb2co
