#include "options.h"

#include "serial_command.h"
#include "timing/latency.h"

namespace mb2co {
namespace timing_cli {
namespace {

std::string num(uint64_t v) {
  return std::to_string(v);
}

/// Options every command takes.
std::vector<cli::Option> common_options(const char* bitrate_default) {
  return {
      cli::bitrate("--bitrate", 1000, timing::kMaxBitrateBps,
                   std::string("CAN bit rate: 125k, 500k, 1M or bit/s (") + bitrate_default + ")"),
      cli::choice("--frame-bits", {"course", "davis"}, "worst-case stuffing bound (default davis)"),
      cli::flag("--json", "JSON instead of a table"),
      cli::flag("--csv", "CSV rows instead of a table"),
  };
}

/// --line N and the CANopen configuration of its stations (node IDs 1..N).
std::vector<cli::Option> line_options() {
  const timing::LineCanConfig c;
  return {
      cli::uint_range("--line", "N", 1, timing::kMaxStations,
                      "the message set of N stations instead of a CSV (default " + num(c.stations) + ")"),
      cli::flag("--no-tpdo1", "line: no event-driven TPDO1"),
      cli::uint_range("--tpdo-dlc", "N", 0, 8, "line: TPDO1 DLC (default " + num(c.tpdo1_dlc) + ")"),
      cli::uint_range("--tpdo-inhibit-100us", "N", 0, UINT16_MAX,
                      "line: TPDO1 inhibit time, 100 us units (default " + num(c.tpdo1_inhibit_100us) + ")"),
      cli::uint_range("--tpdo-event-ms", "MS", 0, UINT16_MAX,
                      "line: TPDO1 event timer (default " + num(c.tpdo1_event_timer_ms) + ")"),
      cli::uint_range(
          "--tpdo-deadline-us", "US", 0, UINT32_MAX,
          "line: TPDO1 deadline, 0 = its inhibit time (default " + num(c.tpdo1_deadline_us) + ")"),
      cli::uint_range("--heartbeat-ms", "MS", 0, UINT16_MAX,
                      "line: heartbeat period (default " + num(c.heartbeat_ms) + ")"),
      cli::uint_range("--sync-us", "US", 0, UINT32_MAX,
                      "line: SYNC period, 0 = none (default " + num(c.sync_period_us) + ")"),
      cli::uint_range("--sync-tpdos", "N", 0, timing::kMaxSyncTpdos,
                      "line: synchronous TPDOs per station (default " + num(c.sync_tpdos) + ")"),
      cli::uint_range("--sync-dlc", "N", 0, 8, "line: their DLC (default " + num(c.sync_tpdo_dlc) + ")"),
      cli::uint_range("--sync-type", "N", 1, 240,
                      "line: their transmission type (default " + num(c.sync_transmission_type) + ")"),
      cli::uint_range("--jitter-us", "US", 0, UINT32_MAX,
                      "line: queuing jitter of every message (default " + num(c.queue_jitter_us) + ")"),
  };
}

std::vector<cli::Option> latency_options() {
  const timing::LatencyParams lat;
  return {
      cli::uint_range("--button-node", "N", 1, timing::kMaxStations,
                      "node of the button (default " + num(kDefaultButtonNode) + ")"),
      cli::uint_range("--pc-node", "N", 1, timing::kMaxStations,
                      "node of the PC's gateway (default " + num(kDefaultPcNode) + ")"),
      cli::uint_range("--baud", "N", 1, 10000000,
                      "Modbus/RTU baud rate (default " + num(lat.serial.baud) + ")"),
      cli::parity("--parity", std::string("Modbus/RTU parity (default ") +
                                  modbus::parity_letter(lat.serial.parity) + ")"),
      cli::uint_range("--stop-bits", "N", 1, 2, "stop bits (default " + num(lat.serial.stop_bits) + ")"),
      cli::uint_range("--debounce-us", "US", 0, 100000000,
                      "button debounce (default " + num(lat.debounce_us) + ")"),
      cli::uint_range("--fw-loop-us", "US", 0, 100000000,
                      "firmware loop pass (default " + num(lat.fw_loop_us) + ")"),
      cli::uint_range("--pc-cycle-us", "US", 0, 100000000,
                      "PC control cycle (default " + num(lat.pc_cycle_us) + ")"),
      cli::uint_range("--pc-compute-us", "US", 0, 100000000,
                      "PC compute time per cycle (default " + num(lat.pc_compute_us) + ")"),
      cli::uint_range("--master-end-us", "US", 0, 100000000,
                      "Modbus master turnaround (default " + num(lat.master_end_us) + ")"),
      cli::flag("--no-t35", "the slave answers without waiting t3.5"),
  };
}

std::vector<cli::Option> join(std::vector<cli::Option> a, const std::vector<cli::Option>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

cli::Program make_program() {
  cli::Program p;
  p.name = "mb2co-timing";
  p.description = "Timing analysis of a CAN/CANopen line (seed 000 §2.9-2.13, §11).\n";
  cli::Command frame{"frame", "frame length in bits and transmission time (all DLCs, or one exact frame)", "",
                     0,
                     join(common_options("default 1M"),
                          {cli::uint_range("--dlc", "N", 0, 8, "only this DLC (default: all 0..8)"),
                           cli::flag("--ext", "29-bit identifier"),
                           cli::text("--id", "X", "exact length of this frame's identifier (0x.. hex)"),
                           cli::text("--data", "HEX", "its data bytes, e.g. 0102ff (needs --id)"),
                           cli::flag("--rtr", "a remote frame (needs --id)")})};
  const std::vector<cli::Option> set =
      join(common_options("needed with FILE.csv; --line: 1M"), line_options());
  cli::Command load{"load", "bus load and utilisation of a message set (FILE.csv or --line N)", "[FILE.csv]",
                    1,
                    join(set, {cli::uint_range("--window-us", "US", 1, UINT32_MAX,
                                               "also the worst-case bits in a window of US")})};
  cli::Command rta{"rta", "worst-case response times: first attempt and revised analysis", "[FILE.csv]", 1,
                   join(set, {cli::flag("--check", "exit 3 unless every deadline is met"),
                              cli::file("--svg", "OUT.svg", "draw the worst-case busy period of --message"),
                              cli::text("--message", "NAME", "the message --svg draws")})};
  cli::Command latency{"latency", "button-to-LED bound, Modbus only and Modbus + CANopen", "", 0,
                       join(set, latency_options())};
  p.commands = {frame, load, rta, latency, serial_command()};
  p.footer =
      "\nCSV columns: name,id,ext,dlc,period_us[,deadline_us,jitter_us,c_us,bits]\n"
      "exit status: 0 done, 1 runtime error, 2 usage error (one line on stderr), 3 rta --check found a "
      "miss\n";
  return p;
}

}  // namespace

const cli::Program& program() {
  static const cli::Program p = make_program();
  return p;
}

Options options_of(const cli::Args& args) {
  Options o;
  const std::string& name = args.command->name;
  o.command = name == "frame" ? kFrame : name == "load" ? kLoad : name == "rta" ? kRta : kLatency;
  o.positional = args.operands;
  o.args = args;
  return o;
}

Status uint_option(const Options& o, const std::string& name, uint64_t min, uint64_t max, uint64_t fallback,
                   uint64_t* value) {
  if (!o.has(name)) {
    *value = fallback;
    return Status::ok();
  }
  return cli::parse_uint(name, o.get(name), min, max, value);
}

Status format_option(const Options& o, Format* format) {
  if (o.has("--json") && o.has("--csv")) {
    return Status::failure("choose one of --json and --csv");
  }
  *format = o.has("--json") ? Format::kJson : o.has("--csv") ? Format::kCsv : Format::kTable;
  return Status::ok();
}

Status frame_bits_option(const Options& o, timing::WorstCase* convention) {
  // The table allows only course and davis.
  *convention = o.get("--frame-bits") == "course" ? timing::WorstCase::kCourse : timing::WorstCase::kDavis;
  return Status::ok();
}

const char* frame_bits_name(timing::WorstCase convention) {
  return convention == timing::WorstCase::kCourse ? "course" : "davis";
}

Status line_config_option(const Options& o, timing::LineCanConfig* cfg) {
  timing::LineCanConfig c;
  uint64_t v = 0;
  auto take = [&](const char* name, uint64_t min, uint64_t max, uint64_t fallback) {
    return uint_option(o, name, min, max, fallback, &v);
  };
  Status s = take("--line", 1, timing::kMaxStations, c.stations);
  if (!s) return s;
  c.stations = static_cast<uint8_t>(v);
  c.bitrate_bps = o.args.bitrate_bps("--bitrate", c.bitrate_bps);
  c.tpdo1 = !o.has("--no-tpdo1");
  if (!(s = take("--tpdo-dlc", 0, 8, c.tpdo1_dlc))) return s;
  c.tpdo1_dlc = static_cast<uint8_t>(v);
  if (!(s = take("--tpdo-inhibit-100us", 0, UINT16_MAX, c.tpdo1_inhibit_100us))) return s;
  c.tpdo1_inhibit_100us = static_cast<uint16_t>(v);
  if (!(s = take("--tpdo-event-ms", 0, UINT16_MAX, c.tpdo1_event_timer_ms))) return s;
  c.tpdo1_event_timer_ms = static_cast<uint16_t>(v);
  if (!(s = take("--tpdo-deadline-us", 0, UINT32_MAX, c.tpdo1_deadline_us))) return s;
  c.tpdo1_deadline_us = static_cast<uint32_t>(v);
  if (!(s = take("--heartbeat-ms", 0, UINT16_MAX, c.heartbeat_ms))) return s;
  c.heartbeat_ms = static_cast<uint16_t>(v);
  if (!(s = take("--sync-us", 0, UINT32_MAX, c.sync_period_us))) return s;
  c.sync_period_us = static_cast<uint32_t>(v);
  if (!(s = take("--sync-tpdos", 0, timing::kMaxSyncTpdos, c.sync_tpdos))) return s;
  c.sync_tpdos = static_cast<uint8_t>(v);
  if (!(s = take("--sync-dlc", 0, 8, c.sync_tpdo_dlc))) return s;
  c.sync_tpdo_dlc = static_cast<uint8_t>(v);
  if (!(s = take("--sync-type", 1, 240, c.sync_transmission_type))) return s;
  c.sync_transmission_type = static_cast<uint8_t>(v);
  if (!(s = take("--jitter-us", 0, UINT32_MAX, c.queue_jitter_us))) return s;
  c.queue_jitter_us = static_cast<uint32_t>(v);
  *cfg = c;
  return Status::ok();
}

std::string line_status_text(timing::LineStatus status) {
  using timing::LineStatus;
  switch (status) {
    case LineStatus::kOk:
      return "ok";
    case LineStatus::kStations:
      return "--line must be 1..127 stations";
    case LineStatus::kBitrate:
      return "--bitrate must be 1..1000000 bit/s";
    case LineStatus::kNoInterArrival:
      return "event-driven TPDO1 needs --tpdo-inhibit-100us > 0 (its minimum inter-arrival "
             "time)";
    case LineStatus::kEventTimer:
      return "--tpdo-event-ms must be 0 or at least the inhibit time";
    case LineStatus::kSyncTpdos:
      return "--sync-tpdos needs --sync-us > 0";
    case LineStatus::kTransmissionType:
      return "--sync-type times --sync-us exceeds 4294967295 us";
    case LineStatus::kDlc:
      return "a DLC above 8";
    case LineStatus::kCapacity:
      return "too many messages";
  }
  return "invalid line configuration";
}

}  // namespace timing_cli
}  // namespace mb2co
