#include "options.h"

namespace mb2co {
namespace lab {
namespace {

cli::Program make_program() {
  cli::Program p;
  p.name = "mb2co-lab";
  p.description =
      "Simulates the production line (gateways with the real firmware core on a\n"
      "bit-timed CAN bus, PCs with the real plant and controller over Modbus/RTU)\n"
      "in virtual time and prints a report; files go to --out.\n";
  const std::vector<uint32_t>& rates = cli::can_bitrates();
  p.commands = {cli::Command{
      "",
      "",
      "",
      0,
      {
          cli::choice("--scenario",
                      {"run", "stop2", "latency", "faults", "sync-roundtrip", "sync-latency",
                       "sync-processing", "alternative", "default"},
                      "default: stop2 then latency"),
          cli::uint_range("--stations", "N", 2, 32, "stations in the line (default 4)"),
          cli::uint_range("--seed", "N", 0, UINT64_MAX, "random seed (default 1): same seed, same report"),
          cli::bitrate_list("--bitrates", rates,
                            "CAN bit rates for latency, e.g. 125k,1M (default all: 125k,250k,500k,1M)"),
          cli::uint_range("--presses", "N", 1, 1000000, "button presses per latency case (default 1000)"),
          cli::flag("--worst",
                    "latency: press at the phasings the bound assumes (a deterministic\n"
                    "search) instead of --presses presses at random phases"),
          cli::uint_range("--duration", "S", 4, 86400,
                          "simulated seconds of the run scenario (default 30; a run too\n"
                          "short for every station to fill a bottle is refused)"),
          cli::uint_range("--pc-cycle-ms", "N", 5, 100, "PC control cycle (default 20)"),
          cli::uint_range("--pc-jitter-us", "N", 0, 100000,
                          "PC cycle start jitter, below the cycle (default 1000)"),
          cli::choice("--firmware", {"uno", "fast"}, "uno: ATmega328P pass times (default); fast: 1 ms loop"),
          cli::flag("--ring", "stations in a ring instead of a chain"),
          cli::uint_range("--can-rx-buffers", "N", 1, 64,
                          "frames the CAN controller holds between passes (default 2, MCP2515)"),
          cli::dir("--out", "DIR", "output directory (default out)"),
          cli::file("--trace", "FILE",
                    "every CAN frame of the runs as a candump -L log (canplayer, Wireshark),\n"
                    "or pcap (LINKTYPE_CAN_SOCKETCAN) when FILE ends in .pcap"),
          cli::flag("--quiet", "no progress bar, no speed figure"),
          cli::flag("--events",
                    "also write events.csv to --out: every event of the runs (CAN\n"
                    "frames, Modbus transactions, LEDs, states; ~30 MB for the default run)"),
          cli::uint_range(
              "--syncs", "N", 1, 1000000,
              "SYNC round trips per bit rate (sync-roundtrip), SYNCs (sync-processing); default 1000"),
          cli::uint_range("--sync-period-us", "N", 1000, 1000000,
                          "SYNC producer's communication cycle period 1006h (default 10000)"),
          cli::uint_range("--transmission-type", "N", 1, 240,
                          "the synchronous TPDO is sent at every N-th SYNC (default 1)"),
          cli::uint_range("--bound-sync-period-us", "N", 1, 1000000,
                          "let the sync-latency bound assume this SYNC period (a wrong bound must FAIL)"),
          cli::file("--elf", "FILE", "sync-processing: the AVR image (default: the built gateway image)"),
      }}};
  p.footer = "\nexit status: 0 every verdict passed, 3 some verdict failed, 2 usage error, 1 runtime error\n";
  return p;
}

}  // namespace

const cli::Program& program() {
  static const cli::Program p = make_program();
  return p;
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
    case Scenario::kSyncRoundtrip:
      return "sync-roundtrip";
    case Scenario::kSyncLatency:
      return "sync-latency";
    case Scenario::kSyncProcessing:
      return "sync-processing";
    case Scenario::kAlternative:
      return "alternative";
    default:
      return "default";
  }
}

Status apply_options(const cli::Args& a, Options* o) {
  const std::string scenario = a.get("--scenario", "default");
  o->scenario = scenario == "run"               ? Scenario::kRun
                : scenario == "stop2"           ? Scenario::kStop2
                : scenario == "latency"         ? Scenario::kLatency
                : scenario == "faults"          ? Scenario::kFaults
                : scenario == "sync-roundtrip"  ? Scenario::kSyncRoundtrip
                : scenario == "sync-latency"    ? Scenario::kSyncLatency
                : scenario == "sync-processing" ? Scenario::kSyncProcessing
                : scenario == "alternative"     ? Scenario::kAlternative
                                                : Scenario::kDefault;
  o->line.stations = static_cast<int>(a.uint("--stations", static_cast<uint64_t>(o->line.stations)));
  o->line.seed = a.uint("--seed", o->line.seed);
  o->line.ring = a.has("--ring") || o->line.ring;
  if (a.has("--bitrates")) {
    o->bitrates.clear();
    for (const uint32_t bps : a.bitrates_bps("--bitrates", {})) o->bitrates.push_back(bps / 1000u);
  }
  o->presses = static_cast<uint32_t>(a.uint("--presses", o->presses));
  o->worst = a.has("--worst");
  o->duration_s = static_cast<uint32_t>(a.uint("--duration", o->duration_s));
  const uint64_t pc_cycle_ms = a.uint("--pc-cycle-ms", 20);
  const uint64_t pc_jitter_us = a.uint("--pc-jitter-us", 1000);
  const uint64_t rx_buffers = a.uint("--can-rx-buffers", 2);
  o->firmware = a.get("--firmware", o->firmware);
  o->out_dir = a.get("--out", o->out_dir);
  o->trace_path = a.get("--trace", o->trace_path);
  o->quiet = a.has("--quiet");
  o->events = a.has("--events");
  o->syncs = static_cast<uint32_t>(a.uint("--syncs", o->syncs));
  o->sync_period_us = static_cast<uint32_t>(a.uint("--sync-period-us", o->sync_period_us));
  o->transmission_type = static_cast<uint32_t>(a.uint("--transmission-type", o->transmission_type));
  o->bound_sync_period_us = static_cast<uint32_t>(a.uint("--bound-sync-period-us", o->bound_sync_period_us));
  o->elf = a.get("--elf", o->elf);
  o->line.pc.cycle_ns = pc_cycle_ms * sim::kNsPerMs;
  o->line.pc.jitter_ns = pc_jitter_us * sim::kNsPerUs;
  if (o->line.pc.jitter_ns >= o->line.pc.cycle_ns) {
    return Status::failure("--pc-jitter-us must be below the PC cycle");
  }
  o->line.node = o->firmware == "fast" ? sim::fast_timing() : sim::uno_timing();
  o->line.node.can_rx_buffers = static_cast<size_t>(rx_buffers);
  if (o->worst && o->scenario != Scenario::kLatency) {
    return Status::failure("--worst needs --scenario latency");
  }
  if ((o->scenario == Scenario::kFaults) && o->line.stations < 4) {
    return Status::failure("--scenario faults needs --stations 4 or more");
  }
  return Status::ok();
}

}  // namespace lab
}  // namespace mb2co
