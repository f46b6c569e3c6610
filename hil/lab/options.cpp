#include "options.h"

#include <cstdlib>
#include <cstring>

namespace mb2co {
namespace lab {
namespace {

bool parse_uint(const std::string& text, uint64_t min, uint64_t max, uint64_t* out) {
  if (text.empty() || text.size() > 20) return false;
  uint64_t v = 0;
  for (char ch : text) {
    if (ch < '0' || ch > '9') return false;
    const uint64_t d = static_cast<uint64_t>(ch - '0');
    if (v > (UINT64_MAX - d) / 10) return false;
    v = v * 10 + d;
  }
  if (v < min || v > max) return false;
  *out = v;
  return true;
}

/// "125", "125k", "1M", "1000" → kbit/s.
bool parse_bitrate(std::string t, uint32_t* kbit) {
  uint64_t mult = 1;
  if (!t.empty() && (t.back() == 'k' || t.back() == 'K'))
    t.pop_back();
  else if (!t.empty() && (t.back() == 'M' || t.back() == 'm')) {
    t.pop_back();
    mult = 1000;
  }
  uint64_t v = 0;
  if (!parse_uint(t, 1, 1000000, &v)) return false;
  v *= mult;
  if (v != 125 && v != 250 && v != 500 && v != 1000) return false;
  *kbit = static_cast<uint32_t>(v);
  return true;
}

}  // namespace

const char* usage() {
  return "usage: mb2co-lab [options]\n"
         "Simulates the production line (gateways with the real firmware core on a\n"
         "bit-timed CAN bus, PCs with the real plant and controller over Modbus/RTU)\n"
         "in virtual time and prints a report; files go to --out.\n"
         "\n"
         "  --scenario S     run | stop2 | latency | faults | default (stop2 then latency)\n"
         "  --stations N     stations in the line, 2..32 (default 4)\n"
         "  --seed N         random seed (default 1): same seed, same report\n"
         "  --bitrates LIST  CAN bit rates for latency, kbit/s: 125,250,500,1000 (default all)\n"
         "  --presses N      button presses per latency case (default 1000)\n"
         "  --duration S     simulated seconds of the run scenario (default 30; a run too\n"
         "                   short for every station to fill a bottle is refused)\n"
         "  --pc-cycle-ms N  PC control cycle (default 20)\n"
         "  --pc-jitter-us N PC cycle start jitter, 0..cycle (default 1000)\n"
         "  --firmware F     uno (ATmega328P pass times, default) | fast (1 ms loop)\n"
         "  --ring           stations in a ring instead of a chain\n"
         "  --can-rx-buffers N  frames the CAN controller holds between passes (default 2, MCP2515)\n"
         "  --out DIR        output directory (default out)\n"
         "  --trace FILE     every CAN frame of the runs as a candump -L log (canplayer, Wireshark)\n"
         "  --quiet          no progress bar, no speed figure\n"
         "  --help           this text\n";
}

const char* scenario_name(Scenario s) {
  switch (s) {
    case Scenario::kRun:
      return "run";
    case Scenario::kStop2:
      return "stop2";
    case Scenario::kLatency:
      return "latency";
    case Scenario::kFaults:
      return "faults";
    default:
      return "default";
  }
}

Status parse_options(int argc, char** argv, Options* o) {
  uint64_t pc_cycle_ms = 20;
  uint64_t rx_buffers = 2;
  uint64_t pc_jitter_us = 1000;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string* v) {
      if (i + 1 >= argc) {
        return Status::failure("option " + a + " needs a value");
      }
      *v = argv[++i];
      return Status::ok();
    };
    Status s;
    std::string v;
    uint64_t n = 0;
    if (a == "--help" || a == "-h") {
      o->help = true;
    } else if (a == "--quiet") {
      o->quiet = true;
    } else if (a == "--ring") {
      o->line.ring = true;
    } else if (a == "--scenario") {
      if (!(s = value(&v))) return s;
      if (v == "run")
        o->scenario = Scenario::kRun;
      else if (v == "stop2")
        o->scenario = Scenario::kStop2;
      else if (v == "latency")
        o->scenario = Scenario::kLatency;
      else if (v == "faults")
        o->scenario = Scenario::kFaults;
      else if (v == "default")
        o->scenario = Scenario::kDefault;
      else {
        return Status::failure("--scenario must be run, stop2, latency, faults or default, got \"" + v +
                               "\"");
      }
    } else if (a == "--stations") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 2, 32, &n)) {
        return Status::failure("--stations must be 2..32, got \"" + v + "\"");
      }
      o->line.stations = static_cast<int>(n);
    } else if (a == "--seed") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 0, UINT64_MAX, &n)) {
        return Status::failure("--seed must be an unsigned integer, got \"" + v + "\"");
      }
      o->line.seed = n;
    } else if (a == "--bitrates") {
      if (!(s = value(&v))) return s;
      o->bitrates.clear();
      size_t start = 0;
      while (start <= v.size()) {
        const size_t comma = v.find(',', start);
        const std::string item =
            v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        uint32_t kbit = 0;
        if (!parse_bitrate(item, &kbit)) {
          return Status::failure("--bitrates: \"" + item + "\" is not 125, 250, 500 or 1000 (kbit/s)");
        }
        o->bitrates.push_back(kbit);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    } else if (a == "--presses") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 1, 1000000, &n)) {
        return Status::failure("--presses must be 1..1000000, got \"" + v + "\"");
      }
      o->presses = static_cast<uint32_t>(n);
    } else if (a == "--duration") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 4, 86400, &n)) {
        return Status::failure("--duration must be 4..86400 seconds, got \"" + v + "\"");
      }
      o->duration_s = static_cast<uint32_t>(n);
    } else if (a == "--pc-cycle-ms") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 5, 100, &pc_cycle_ms)) {
        return Status::failure("--pc-cycle-ms must be 5..100, got \"" + v + "\"");
      }
    } else if (a == "--pc-jitter-us") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 0, 100000, &pc_jitter_us)) {
        return Status::failure("--pc-jitter-us must be 0..100000, got \"" + v + "\"");
      }
    } else if (a == "--can-rx-buffers") {
      if (!(s = value(&v))) return s;
      if (!parse_uint(v, 1, 64, &rx_buffers)) {
        return Status::failure("--can-rx-buffers must be 1..64, got \"" + v + "\"");
      }
    } else if (a == "--firmware") {
      if (!(s = value(&v))) return s;
      if (v != "uno" && v != "fast") {
        return Status::failure("--firmware must be uno or fast, got \"" + v + "\"");
      }
      o->firmware = v;
    } else if (a == "--out") {
      if (!(s = value(&v))) return s;
      if (v.empty()) {
        return Status::failure("--out needs a directory");
      }
      o->out_dir = v;
    } else if (a == "--trace") {
      if (!(s = value(&v))) return s;
      if (v.empty()) return Status::failure("--trace needs a file");
      o->trace_path = v;
    } else {
      return Status::failure("unknown option \"" + a + "\" (see --help)");
    }
  }
  o->line.pc.cycle_ns = pc_cycle_ms * sim::kNsPerMs;
  o->line.pc.jitter_ns = pc_jitter_us * sim::kNsPerUs;
  if (o->line.pc.jitter_ns >= o->line.pc.cycle_ns) {
    return Status::failure("--pc-jitter-us must be below the PC cycle");
  }
  o->line.node = o->firmware == "fast" ? sim::fast_timing() : sim::uno_timing();
  o->line.node.can_rx_buffers = static_cast<size_t>(rx_buffers);
  if ((o->scenario == Scenario::kFaults) && o->line.stations < 4) {
    return Status::failure("--scenario faults needs --stations 4 or more");
  }
  return Status::ok();
}

}  // namespace lab
}  // namespace mb2co
