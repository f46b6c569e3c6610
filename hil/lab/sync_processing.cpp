#include "sync_processing.h"

#include <filesystem>

#include "canopen/sdo_client.h"
#include "histogram_svg.h"
#include "platform/device_port.h"
#include "sim/event_log.h"
#include "sim/lab_bound.h"
#include "sim/node_timing.h"
#include "sim/rng.h"
#include "uno_rig.h"

namespace mb2co {
namespace lab {

using sim::strf;

namespace {

constexpr uint64_t kCyclesPerUs = uno::UnoBoard::kCpuHz / 1000000u;
constexpr uint32_t kSyncCobId = 0x80;

CanFrame frame(uint32_t id, uint8_t dlc, const uint8_t* data) {
  CanFrame f{};
  f.id = id;
  f.dlc = dlc;
  for (uint8_t i = 0; i < dlc; ++i) f.data[i] = data[i];
  return f;
}

class Bench {
 public:
  explicit Bench(SyncProcessingResult& r) : r_(r) {}

  bool boot(const std::string& elf) {
    const Status loaded = rig_.load(elf);
    if (!loaded) return fail(loaded.message());
    while (rig_.booted_node() == 0) {
      if (!run_for_us(1000) || rig_.now_us() > 3000000) return fail("no boot-up message within 3 s");
    }
    r_.node_id = rig_.booted_node();
    return true;
  }

  // The master's SDO client (shared/canopen) writes the `size` low bytes of
  // `value`, as a student's tool would.
  bool sdo_write(uint16_t index, uint8_t sub, uint32_t value, uint8_t size) {
    const uint8_t data[4] = {static_cast<uint8_t>(value), static_cast<uint8_t>(value >> 8),
                             static_cast<uint8_t>(value >> 16), static_cast<uint8_t>(value >> 24)};
    canopen::SdoClient client;
    client.init(r_.node_id);
    const CanSink sink{&Bench::to_image, this};
    if (!client.start_download(index, sub, canopen::kSdoAuto, data, size, now32(), sink)) {
      return fail("SDO client busy");
    }
    while (client.busy()) {
      if (!run_for_us(100)) return false;
      for (const uno::CanWire::Sent& s : rig_.take_can_out()) {
        if (s.frame.id == client.response_id()) client.on_frame(s.frame, now32(), sink);
      }
      client.process(now32(), sink);
    }
    if (client.status() == canopen::SdoClient::kDone) return true;
    return fail(
        strf("SDO write %04Xh/%u ended with abort %08X", index, sub, static_cast<uint32_t>(client.result())));
  }

  bool start_node() {
    const uint8_t d[2] = {0x01, r_.node_id};  // NMT start remote node
    rig_.can_in(frame(0x000, 2, d));
    return run_for_us(20000);
  }

  // One SYNC from an idle wire: cycles from its reception to the PDO's request.
  bool one_sync(uint32_t pdo_id) {
    while (rig_.wire_busy_until() != uno::CanWire::kIdle) {
      if (!run_for_us(50)) return false;
    }
    rig_.take_can_out();
    rig_.can_in(frame(kSyncCobId, 0, nullptr));
    const uint64_t received = rig_.wire_busy_until();
    uint64_t requested = 0;
    rig_.on_transmit_request = [&](uint64_t cycle, const CanFrame& f) {
      if (requested == 0 && f.id == pdo_id && cycle >= received) requested = cycle;
    };
    const uint64_t until = rig_.now_us() + 20000;
    while (requested == 0 && rig_.now_us() < until) {
      if (!run_for_us(50)) break;
    }
    rig_.on_transmit_request = nullptr;
    if (requested == 0)
      return fail(strf("no PDO %03Xh within 20 ms of SYNC %zu", pdo_id, r_.cycles.size() + 1));
    r_.cycles.push_back(requested - received);
    return true;
  }

  bool run_for_us(uint64_t us) {
    if (rig_.run_until_us(rig_.now_us() + us)) return true;
    return fail("the CPU stopped: " + rig_.board().stop_reason());
  }

 private:
  static bool to_image(void* ctx, const CanFrame& f) {
    static_cast<Bench*>(ctx)->rig_.can_in(f);
    return true;
  }
  uint32_t now32() const { return static_cast<uint32_t>(rig_.now_us()); }

  bool fail(const std::string& why) {
    if (r_.error.empty()) r_.error = why;
    return false;
  }

  SyncProcessingResult& r_;
  uno::UnoRig rig_;
};

}  // namespace

SyncProcessingResult sync_processing_run(const std::string& elf_path, uint32_t syncs, uint64_t seed) {
  SyncProcessingResult r;
  r.elf = elf_path;
  r.wanted = syncs;
  const sim::NodeTiming uno = sim::uno_timing();
  const sim::SimNs pass_max = sim::max_pass_ns(uno, uno.can_rx_buffers, 0, 0);
  r.pass_max_us = pass_max / sim::kNsPerUs;
  r.bound_us = sim::firmware_step_ns(uno, pass_max) / sim::kNsPerUs;
  Bench bench(r);
  if (!bench.boot(elf_path)) return r;
  const uint32_t pdo = 0x280u + r.node_id;  // TPDO2 (buttons, 6000h/1)
  // TPDO2 synchronous, every SYNC: disable, set the type, enable (CiA 301).
  if (!bench.sdo_write(0x1801, 1, 0x80000000u | pdo, 4) || !bench.sdo_write(0x1801, 2, 1, 1) ||
      !bench.sdo_write(0x1801, 1, pdo, 4) || !bench.start_node()) {
    return r;
  }
  sim::Rng rng(sim::mix_seed(seed, 5100));
  for (uint32_t i = 0; i < syncs; ++i) {
    if (!bench.run_for_us(rng.range(3000, 8000)) || !bench.one_sync(pdo)) break;
  }
  if (!r.cycles.empty()) {
    r.min_cycles = r.max_cycles = r.cycles.front();
    long double sum = 0;
    for (uint64_t c : r.cycles) {
      r.min_cycles = c < r.min_cycles ? c : r.min_cycles;
      r.max_cycles = c > r.max_cycles ? c : r.max_cycles;
      sum += static_cast<long double>(c);
    }
    r.mean_cycles = static_cast<double>(sum / static_cast<long double>(r.cycles.size()));
  }
  r.ok = r.error.empty() && r.cycles.size() == syncs && r.max_cycles <= r.bound_us * kCyclesPerUs;
  return r;
}

std::string sync_processing_section(const SyncProcessingResult& r) {
  std::string s =
      "\n== sync-processing: SYNC received -> response PDO in an MCP2515 transmit buffer, real image (seed "
      "000 "
      "§5.1)\n";
  s += strf(
      "  image: %s, node %u, ATmega328P at 16 MHz in simavr; TPDO2 set synchronous by SDO (1801h/2 = 1)\n",
      std::filesystem::path(r.elf).filename().string().c_str(), r.node_id);
  s += strf("  %-8s %5s %9s %9s %9s  | %9s\n", "", "n", "min", "mean", "max", "bound");
  s += strf("  %-8s %5zu %9llu %9.0f %9llu  | %9llu\n", "cycles", r.cycles.size(),
            static_cast<unsigned long long>(r.min_cycles), r.mean_cycles,
            static_cast<unsigned long long>(r.max_cycles),
            static_cast<unsigned long long>(r.bound_us) * kCyclesPerUs);
  s += strf("  %-8s %5zu %9.2f %9.2f %9.2f  | %9llu\n", "us", r.cycles.size(),
            static_cast<double>(r.min_cycles) / kCyclesPerUs, r.mean_cycles / kCyclesPerUs,
            static_cast<double>(r.max_cycles) / kCyclesPerUs, static_cast<unsigned long long>(r.bound_us));
  s += strf(
      "  bound: the simulator's sync_pass worst case for the uno profile (pass times measured on this "
      "firmware\n"
      "  by firmware/avr/measure-pass-time.sh, sim::uno_timing()): a pass in progress + the pass that hands\n"
      "  the SYNC in, %llu us each at most (%u CAN frames handed in)\n",
      static_cast<unsigned long long>(r.pass_max_us),
      static_cast<unsigned>(sim::uno_timing().can_rx_buffers));
  if (!r.error.empty()) s += "  stopped: " + r.error + "\n";
  if (r.ok) {
    s += strf(
        "verdict sync-processing: PASS (criterion: all %zu SYNCs answered, every count within the bound)\n",
        r.cycles.size());
  } else {
    s += strf(
        "verdict sync-processing: FAIL (criterion: all %u SYNCs answered, every count within the bound; "
        "%zu answered, max %llu cycles)\n",
        r.wanted, r.cycles.size(), static_cast<unsigned long long>(r.max_cycles));
  }
  return s;
}

std::string sync_processing_svg(const SyncProcessingResult& r) {
  HistogramPanel p;
  p.name = std::filesystem::path(r.elf).filename().string() + ", cycles at 16 MHz";
  p.samples = &r.cycles;
  p.min = r.min_cycles;
  p.max = r.max_cycles;
  p.bounded = r.bound_us != 0;
  p.has_best = false;  // the model bounds it from above only
  p.worst = r.bound_us * kCyclesPerUs;
  p.worst_label = "bound";
  const HistogramUnit us_of_cycles = {"us", static_cast<double>(kCyclesPerUs)};
  return histogram_svg("SYNC received to the response PDO in an MCP2515 transmit buffer, real image:",
                       "SYNCs", us_of_cycles, {p});
}

}  // namespace lab
}  // namespace mb2co
