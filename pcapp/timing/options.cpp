#include "options.h"

#include <cstdio>
#include <cstring>

#include "timing/latency.h"

namespace mb2co {
namespace timing_cli {
namespace {

struct OptionSpec {
  const char* name;
  bool takes_value;
  unsigned commands;  // Command bits
};

constexpr unsigned kSets = kLoad | kRta | kLatency;  // commands that analyse a message set
constexpr unsigned kAll = kFrame | kSets;

const OptionSpec kSpecs[] = {
    {"--bitrate", true, kAll},
    {"--frame-bits", true, kAll},
    {"--json", false, kAll},
    {"--csv", false, kAll},
    {"--dlc", true, kFrame},
    {"--ext", false, kFrame},
    {"--id", true, kFrame},
    {"--data", true, kFrame},
    {"--rtr", false, kFrame},
    {"--window-us", true, kLoad},
    {"--svg", true, kRta},
    {"--message", true, kRta},
    {"--check", false, kRta},
    {"--line", true, kSets},
    {"--no-tpdo1", false, kSets},
    {"--tpdo-dlc", true, kSets},
    {"--tpdo-inhibit-100us", true, kSets},
    {"--tpdo-event-ms", true, kSets},
    {"--tpdo-deadline-us", true, kSets},
    {"--heartbeat-ms", true, kSets},
    {"--sync-us", true, kSets},
    {"--sync-tpdos", true, kSets},
    {"--sync-dlc", true, kSets},
    {"--sync-type", true, kSets},
    {"--jitter-us", true, kSets},
    {"--button-node", true, kLatency},
    {"--pc-node", true, kLatency},
    {"--baud", true, kLatency},
    {"--parity", true, kLatency},
    {"--stop-bits", true, kLatency},
    {"--debounce-us", true, kLatency},
    {"--fw-loop-us", true, kLatency},
    {"--pc-cycle-us", true, kLatency},
    {"--pc-compute-us", true, kLatency},
    {"--master-end-us", true, kLatency},
    {"--no-t35", false, kLatency},
};

const OptionSpec* find_spec(const std::string& name) {
  for (const OptionSpec& s : kSpecs) {
    if (name == s.name) return &s;
  }
  return nullptr;
}

}  // namespace

Status parse_options(int argc, char** argv, Options& out) {
  const std::string command = argv[1];
  if (command == "frame") {
    out.command = kFrame;
  } else if (command == "load") {
    out.command = kLoad;
  } else if (command == "rta") {
    out.command = kRta;
  } else if (command == "latency") {
    out.command = kLatency;
  } else {
    return Status::failure("unknown command \"" + command + "\" (expected frame, load, rta or latency)");
  }
  for (int i = 2; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.size() < 2 || arg.compare(0, 2, "--") != 0) {
      out.positional.push_back(arg);
      continue;
    }
    std::string value;
    bool inline_value = false;
    const size_t eq = arg.find('=');
    if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg.resize(eq);
      inline_value = true;
    }
    const OptionSpec* spec = find_spec(arg);
    if (spec == nullptr || (spec->commands & out.command) == 0) {
      return Status::failure(
          std::string("unknown option ").append(arg).append(" for ").append(command).append(" (see --help)"));
    }
    if (spec->takes_value && !inline_value) {
      if (i + 1 >= argc) {
        return Status::failure("option " + arg + " needs a value");
      }
      value = argv[++i];
    } else if (!spec->takes_value && inline_value) {
      return Status::failure("option " + arg + " takes no value");
    }
    if (!out.values.emplace(arg, value).second) {
      return Status::failure("option " + arg + " given twice");
    }
  }
  return Status::ok();
}

Status uint_option(const Options& o, const std::string& name, uint64_t min, uint64_t max, uint64_t fallback,
                   bool scaled, uint64_t* value) {
  if (!o.has(name)) {
    *value = fallback;
    return Status::ok();
  }
  const std::string& text = o.get(name);
  std::string digits = text;
  uint64_t scale = 1;
  if (scaled && !digits.empty() && (digits.back() == 'k' || digits.back() == 'M')) {
    scale = digits.back() == 'k' ? 1000u : 1000000u;
    digits.pop_back();
  }
  uint64_t v = 0;
  bool ok = !digits.empty() && digits.size() <= 12;
  for (const char c : digits) ok = ok && c >= '0' && c <= '9';
  if (ok) {
    for (const char c : digits) v = v * 10u + static_cast<uint64_t>(c - '0');
    v *= scale;
  }
  if (!ok || v < min || v > max) {
    return Status::failure("option " + name + " must be a whole number " + std::to_string(min) + ".." +
                           std::to_string(max) + ", got \"" + text + "\"");
  }
  *value = v;
  return Status::ok();
}

Status format_option(const Options& o, Format* format) {
  if (o.has("--json") && o.has("--csv")) {
    return Status::failure("choose one of --json and --csv");
  }
  *format = o.has("--json") ? Format::kJson : o.has("--csv") ? Format::kCsv : Format::kTable;
  return Status::ok();
}

Status frame_bits_option(const Options& o, timing::WorstCase* convention) {
  const std::string v = o.has("--frame-bits") ? o.get("--frame-bits") : "davis";
  if (v == "davis") {
    *convention = timing::WorstCase::kDavis;
  } else if (v == "course") {
    *convention = timing::WorstCase::kCourse;
  } else {
    return Status::failure("option --frame-bits must be course or davis, got \"" + v + "\"");
  }
  return Status::ok();
}

const char* frame_bits_name(timing::WorstCase convention) {
  return convention == timing::WorstCase::kCourse ? "course" : "davis";
}

Status line_config_option(const Options& o, timing::LineCanConfig* cfg) {
  timing::LineCanConfig c;
  uint64_t v = 0;
  auto take = [&](const char* name, uint64_t min, uint64_t max, uint64_t fallback) {
    return uint_option(o, name, min, max, fallback, false, &v);
  };
  Status s = take("--line", 1, timing::kMaxStations, c.stations);
  if (!s) return s;
  c.stations = static_cast<uint8_t>(v);
  if (!(s = uint_option(o, "--bitrate", 1, timing::kMaxBitrateBps, c.bitrate_bps, true, &v))) return s;
  c.bitrate_bps = static_cast<uint32_t>(v);
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

std::string usage_text() {
  // Defaults are printed from the structs the commands start from, so the
  // help cannot drift from the code (it did: DLC 2, 500 ms, 1000 ms).
  const timing::LineCanConfig line;
  const timing::LatencyParams lat;
  const char* parity = lat.serial.parity == timing::Parity::kEven  ? "even"
                       : lat.serial.parity == timing::Parity::kOdd ? "odd"
                                                                   : "none";
  char text[2048];
  std::snprintf(text, sizeof text, R"(usage: mb2co-timing COMMAND [options]
Timing analysis of a CAN/CANopen line (seed 000 §2.9-2.13, §11).

commands:
  frame    frame length in bits and transmission time
           --dlc N (default: all 0..8)  --ext  --bitrate B (default 1M)
           exact length of one frame: --id X --data HEX [--ext] [--rtr]
  load     bus load and utilisation of a message set
           FILE.csv | --line N [line options]   --bitrate B   [--window-us W]
  rta      worst-case response times: first attempt and revised analysis
           FILE.csv | --line N [line options]   --bitrate B
           [--check] (exit 3 unless all deadlines met)
           [--svg OUT.svg --message NAME] (worst-case busy period of NAME)
  latency  button-to-LED bound, Modbus only and Modbus + CANopen
           [line options] [--button-node %u] [--pc-node %u] [--baud %lu]
           [--parity even|none|odd (%s)] [--stop-bits 1|2 (%u)] [--debounce-us %lu]
           [--fw-loop-us %lu] [--pc-cycle-us %lu] [--pc-compute-us %lu]
           [--master-end-us %lu] [--no-t35]

common options:
  --frame-bits course|davis   worst-case stuffing bound (default davis)
  --json | --csv              machine-readable output instead of a table
  --bitrate B                 bit/s, k and M suffixes allowed (125k, 1M)

line options (the CANopen configuration of N stations, node IDs 1..N):
  --line N (default %u)  --no-tpdo1  --tpdo-dlc %u  --tpdo-inhibit-100us %u
  --tpdo-event-ms %u  --tpdo-deadline-us %lu  --heartbeat-ms %u
  --sync-us %lu  --sync-tpdos %u  --sync-dlc %u  --sync-type %u  --jitter-us %lu

CSV columns: name,id,ext,dlc,period_us[,deadline_us,jitter_us,c_us,bits]
exit status: 0 done, 1 error (one line on stderr), 3 --check found a miss
)",
                kDefaultButtonNode, kDefaultPcNode, static_cast<unsigned long>(lat.serial.baud), parity,
                lat.serial.stop_bits, static_cast<unsigned long>(lat.debounce_us),
                static_cast<unsigned long>(lat.fw_loop_us), static_cast<unsigned long>(lat.pc_cycle_us),
                static_cast<unsigned long>(lat.pc_compute_us), static_cast<unsigned long>(lat.master_end_us),
                line.stations, line.tpdo1_dlc, line.tpdo1_inhibit_100us, line.tpdo1_event_timer_ms,
                static_cast<unsigned long>(line.tpdo1_deadline_us), line.heartbeat_ms,
                static_cast<unsigned long>(line.sync_period_us), line.sync_tpdos, line.sync_tpdo_dlc,
                line.sync_transmission_type, static_cast<unsigned long>(line.queue_jitter_us));
  return text;
}

}  // namespace timing_cli
}  // namespace mb2co
