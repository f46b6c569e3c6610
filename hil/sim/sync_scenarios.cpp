#include "sim/sync_scenarios.h"

#include "sim/scenario_parts.h"

namespace mb2co {
namespace sim {

using namespace scenario_parts;

namespace {

constexpr uint32_t kSyncCobId = 0x80;
constexpr uint16_t kLabLedEntryHi = 0x6200;
constexpr uint32_t kLabLedEntry = 0x62000108u;  // 6200h/1, 8 bits
// Station 1 (A) sends the SYNC and has the LED; station 2 (B) answers.
constexpr int kStationA = 0;
constexpr int kStationB = 1;
constexpr uint32_t kPdoB = 0x280u + kStationB + 1;  // B's TPDO2 (buttons)
enum : uint64_t { kStreamSyncPresses = 3000, kStreamAlternative = 4000 };

uint32_t ceil_us(SimNs ns) {
  return static_cast<uint32_t>((ns + kNsPerUs - 1) / kNsPerUs);
}

// A's RPDO4 writes B's buttons into A's LED object 6200h/1 (START is bit 0,
// the lab LED): for §5.3 the LED follows B's joystick, for §11 it is A's
// control process (LED := button) whose output A's TPDO3 sends on.
void map_buttons_to_led(canopen::ObjectDictionary& od) {
  static_assert((kLabLedEntry >> 16) == kLabLedEntryHi, "lab LED entry");
  commission_pdo(od, 0x1403, 0x1603, kLabLedEntry, kPdoB);
}

LineConfig sync_line(LineConfig c, const SyncLabConfig& lab) {
  c.bitrate_kbit = lab.bitrate_kbit;
  c.lab_pc = c.lab_remote = -1;
  c.commission_more = [lab](int i, canopen::ObjectDictionary& od) {
    if (i == kStationA) {  // the SYNC producer
      commission_write(od, 0x1006, 0, lab.sync_period_us, 4);
      commission_write(od, 0x1005, 0, 0x40000000u | kSyncCobId, 4);
      map_buttons_to_led(od);
    }
    if (i == kStationB) {  // TPDO2 synchronous: disable, set the type, enable
      commission_write(od, 0x1801, 1, 0x80000000u | kPdoB, 4);
      commission_write(od, 0x1801, 2, lab.transmission_type, 1);
      commission_write(od, 0x1801, 1, kPdoB, 4);
    }
  };
  return c;
}

/// The SYNC lab's line; the log's run is named `name`-<bit rate>k.
LineConfig logged(const LineConfig& c, const SyncLabConfig& lab, EventLog* log, const char* name) {
  if (log) log->set_run(strf("%s-%uk", name, lab.bitrate_kbit));
  return sync_line(c, lab);
}

/// One SYNC lab run: its result and its line, powered on.
struct SyncRun {
  SyncRun(const LineConfig& c, const SyncLabConfig& lab, uint32_t wanted, EventLog* log, const char* name)
      : line(logged(c, lab, log, name), log) {
    r.lab = lab;
    r.wanted = wanted;
    line.power_on_all();
  }
  SyncResult r;
  Line line;
};

// The bound for the line as commissioned (every Arduino up).
void bound(Line& line, const SyncLabConfig& lab, SyncResult& r, bool response) {
  const Status found = sync_params_for(line, lab, &r.params);
  r.bound_ok = found.is_ok();
  if (!found) r.error = found.message();
  if (r.bound_ok)
    r.bound = response ? timing::sync_response_bound(r.params) : timing::sync_round_trip_bound(r.params);
}

void finish(Line& line, SyncResult& r) {
  r.duration_ns = line.now();
  r.events = line.queue().handled();
  r.stats = sample_stats(r.samples_ns);
  if (r.bound_ok) {
    for (SimNs v : r.samples_ns) {
      if (v < r.bound.best_ns || v > r.bound.worst_ns) ++r.outside;
    }
  }
  r.ok = r.bound_ok && r.error.empty() && r.outside == 0 && r.lost == 0 && r.samples_ns.size() == r.wanted;
}

}  // namespace

Status sync_params_for(Line& line, const SyncLabConfig& lab, timing::SyncParams* p) {
  const LineConfig& c = line.config();
  const NodeTiming& nt = c.node;
  // No PC talks to these Arduinos: a pass hands in CAN frames only.
  const SimNs step = firmware_step_ns(nt, max_pass_ns(nt, nt.can_rx_buffers, 0, 0));
  *p = timing::SyncParams{};
  p->bitrate_bps = c.bitrate_kbit * 1000u;
  p->convention = timing::WorstCase::kDavis;
  p->sync_period_us = lab.bound_sync_period_us != 0 ? lab.bound_sync_period_us : lab.sync_period_us;
  p->transmission_type = lab.transmission_type;
  p->fw_loop_us = ceil_us(step);
  // The producer notices its period in the next pass and queues the SYNC at its end.
  p->sync_jitter_us = p->fw_loop_us;
  // The shortest pass that hands in a frame (no jitter drawn).
  p->pass_min_us = static_cast<uint32_t>((nt.pass_ns + nt.frame_ns) / kNsPerUs);
  p->debounce_us = uint32_t{c.debounce_ms} * 1000u;
  std::vector<timing::MessageSpec> messages;
  Status listed = line_can_messages(line, p->fw_loop_us, &messages);
  if (!listed) return listed;
  HopTimes sync, pdo;
  if (!hop_times(messages, kSyncCobId, p->bitrate_bps, &sync) ||
      !hop_times(messages, kPdoB, p->bitrate_bps, &pdo)) {
    return Status::failure(
        strf("no bounded CAN response time for the SYNC or the PDO at %u kbit/s", c.bitrate_kbit));
  }
  for (const timing::MessageSpec& m : messages) {
    if (m.id == kPdoB) p->pdo_dlc = m.dlc;
  }
  p->sync_queueing_worst_ns = sync.worst_ns - sync.frame_worst_ns;
  p->pdo_queueing_worst_ns = pdo.worst_ns - pdo.frame_worst_ns;
  if (!timing::sync_params_valid(*p)) return Status::failure("SYNC parameters out of range");
  return Status::ok();
}

SyncResult sync_roundtrip_scenario(const LineConfig& c, const SyncLabConfig& lab, uint32_t answers,
                                   EventLog* log, const Progress& progress) {
  SyncRun run(c, lab, answers, log, "sync-roundtrip");
  SyncResult& r = run.r;
  Line& line = run.line;
  // Every Arduino is up well before 1 s; from then on each PDO of B is
  // paired with the last SYNC before it. That is its SYNC only when every
  // round trip ends before the next SYNC: a period at or below the worst
  // round trip is refused (the seed sends a SYNC and waits for its answer).
  const SimNs from = kS;
  line.run_until(from);
  bound(line, lab, r, false);
  const SimNs period_ns = SimNs{lab.sync_period_us} * kNsPerUs;
  if (r.bound_ok && r.bound.worst_ns >= period_ns) {
    r.error = strf(
        "not measured: the SYNC period (%u us) is not above the worst round trip (%llu us), an answer "
        "could not be told from the next SYNC's",
        lab.sync_period_us, static_cast<unsigned long long>((r.bound.worst_ns + 999) / 1000));
  }
  if (!r.error.empty()) {
    finish(line, r);
    return r;
  }
  bool pending = false;
  SimNs sync_sof = 0;
  line.on_can = [&](const CanAttempt& a) {
    if (a.error || a.sof_ns < from) return;
    if (a.frame.id == kSyncCobId) {
      ++r.syncs;
      pending = true;
      sync_sof = a.sof_ns;
    } else if (a.frame.id == kPdoB && pending) {
      pending = false;
      if (r.samples_ns.size() < answers) r.samples_ns.push_back(a.end_ns - sync_sof);
    }
  };
  const SimNs end = from + (SimNs{answers} * lab.transmission_type + 2) * period_ns + kS;
  while (r.samples_ns.size() < answers && line.now() < end) {
    line.run_for(100 * kMs);
    if (progress) progress(static_cast<double>(r.samples_ns.size()) / answers);
  }
  line.on_can = nullptr;
  finish(line, r);
  return r;
}

SyncResult sync_latency_scenario(const LineConfig& c, const SyncLabConfig& lab, uint32_t presses,
                                 EventLog* log, const Progress& progress) {
  SyncRun run(c, lab, presses, log, "sync-latency");
  SyncResult& r = run.r;
  Line& line = run.line;
  line.on_can = [&r](const CanAttempt& a) {
    if (!a.error && a.frame.id == kSyncCobId) ++r.syncs;
  };
  Rng rng(mix_seed(c.seed, kStreamOperator + kStreamSyncPresses + lab.bitrate_kbit));
  PressRun pressed = run_presses(line, kStationB, kStationA, presses, rng, progress);
  line.on_can = nullptr;
  r.samples_ns = std::move(pressed.samples_ns);
  r.lost = pressed.lost;
  bound(line, lab, r, true);
  finish(line, r);
  return r;
}

AlternativeResult alternative_scenario(const LineConfig& c, uint32_t bitrate_kbit, uint32_t presses,
                                       EventLog* log, const Progress& progress) {
  AlternativeResult r;
  r.bitrate_kbit = bitrate_kbit;
  auto part = [&progress](double from) {
    return [&progress, from](double f) {
      if (progress) progress((from + f) / 3.0);
    };
  };
  r.modbus = latency_scenario(c, LatencyCase{bitrate_kbit, false}, presses, log, part(0));
  r.canopen = latency_scenario(c, LatencyCase{bitrate_kbit, true}, presses, log, part(1));

  LineConfig a = c;
  a.bitrate_kbit = bitrate_kbit;
  a.lab_pc = kStationA;  // the Arduino running the control process
  a.lab_remote = kStationB;
  a.commission_more = [](int i, canopen::ObjectDictionary& od) {
    if (i == kStationA) map_buttons_to_led(od);
  };
  if (log) log->set_run(strf("alternative-%uk", bitrate_kbit));
  Line line(a, log);
  line.power_on_all();  // no PC program: nothing on the serial lines
  Rng rng(mix_seed(a.seed, kStreamOperator + kStreamAlternative + bitrate_kbit));
  PressRun run = run_presses(line, kStationB, kStationB, presses, rng, part(2));
  LatencyResult& out = r.arduino;
  out.c = LatencyCase{bitrate_kbit, true};
  out.samples_ns = std::move(run.samples_ns);
  out.lost = run.lost;
  out.bound = arduino_control_bound(line);
  out.duration_ns = line.now();
  out.events = line.queue().handled();
  for (int i = 0; i < line.size(); ++i) out.rx_overflows += line.node(i).can().counters().rx_overflows;
  judge_latency(out);
  r.ok = r.modbus.ok && r.canopen.ok && r.arduino.ok;
  return r;
}

}  // namespace sim
}  // namespace mb2co
