#include "modbus/master_codec.h"
#include "sim/scenario_parts.h"
#include "sim/scenarios.h"

namespace mb2co {
namespace sim {

using namespace scenario_parts;

// ---- faults ----------------------------------------------------------------

namespace {

/// One run of the faults scenario: the line, what it observes while the
/// faults happen, and the checks so far. The phases run in the order of the
/// report (frame loss, bus-off, reboot, unplug), each from where the one
/// before left the line; the times are the scenario's own (virtual ns).
class FaultsRun {
 public:
  FaultsRun(const LineConfig& c, EventLog* log, const Progress& progress)
      : c_(c),
        progress_(progress),
        pl_(c, log, "faults"),
        line_(pl_.line),
        consumer_ns_(3u * c.heartbeat_ms * kMs),
        step_ns_(longest_plant_step_ns(c)),
        last_hb_(static_cast<size_t>(c.stations), 0),
        stop2_presses_(static_cast<size_t>(c.stations), 0) {
    watch();
  }

  void running_before_the_faults() {
    bring_up(line_, pl_.rng, progress_, 0.15);
    check_stopped("line running before the faults", {});
  }

  /// A. Frame loss: 2 % of frames destroyed (error frame, retransmission).
  void frame_loss() {
    const uint64_t errors_before = line_.bus().error_frames();
    line_.at(3500 * kMs, [this] {
      line_.note(-1, "fault", "corruption ppm=20000");
      line_.bus().set_corruption_ppm(20000);
    });
    stop2(4000 * kMs, 0);
    line_.run_until(4500 * kMs);
    check_stopped("frame loss: STOP2 at station 1 stops stations 1 and 2", {0, 1});
    press(line_, 5000 * kMs, 0, gateway::kStart);
    press(line_, 5050 * kMs, 1, gateway::kStart);
    line_.at(6500 * kMs, [this] {
      line_.note(-1, "fault", "corruption ppm=0");
      line_.bus().set_corruption_ppm(0);
    });
    run_to(line_, 7000 * kMs, progress_, 0, 0.15, 0.35);
    check("frame loss: error frames seen and retransmitted",
          line_.bus().error_frames() > errors_before && stopped({}).first,
          strf("%llu error frames, line running again: %s",
               static_cast<unsigned long long>(line_.bus().error_frames() - errors_before),
               stopped({}).first ? "yes" : "no"));
  }

  /// B. Bus-off: station 2's transceiver destroys every frame it sends for 2 s.
  void bus_off() {
    const SimNs b0 = 7000 * kMs;
    line_.at(b0, [this] {
      line_.note(1, "fault", "tx broken");
      line_.node(1).can().set_tx_broken(true);
    });
    stop2(7500 * kMs, 1);
    line_.at(9000 * kMs, [this] {
      line_.note(1, "fault", "tx repaired");
      line_.node(1).can().set_tx_broken(false);
    });
    line_.run_until(8600 * kMs);
    {
      auto d = detection(1, b0);
      check("bus-off: station 2 went bus-off", line_.node(1).can().counters().bus_offs > 0,
            strf("%llu bus-off entries",
                 static_cast<unsigned long long>(line_.node(1).can().counters().bus_offs)));
      check("bus-off: neighbours show station 2 unknown within the consumer time", d.first, d.second);
      check_stopped("bus-off: STOP2 at station 2 stops it at once (station 3 not told yet)", {1});
    }
    line_.run_until(9800 * kMs);
    check_stopped("bus-off: after recovery the STOP2 reaches station 3", {1, 2});
    press(line_, 10000 * kMs, 1, gateway::kStart);
    press(line_, 10050 * kMs, 2, gateway::kStart);
    run_to(line_, 11000 * kMs, progress_, 0, 0.35, 0.55);
  }

  /// C. Neighbour reboot: station 3 powered off for 1 s.
  void reboot() {
    const SimNs c0 = 11500 * kMs;
    line_.at(c0, [this] { line_.power(2, false); });
    line_.at(12000 * kMs, [this] { safe_during_outage_[0] = safe_now(2); });
    line_.at(12500 * kMs, [this] { line_.power(2, true); });
    line_.run_until(12500 * kMs);
    {
      auto d = detection(2, c0);
      check("reboot: neighbours show station 3 unknown within the consumer time", d.first, d.second);
      check_kept_safe("reboot: PC 3 lost its link and kept its plant safe", 2, safe_during_outage_[0]);
    }
    press(line_, 13500 * kMs, 2, gateway::kStart);
    run_to(line_, 14500 * kMs, progress_, 0, 0.55, 0.75);
    auto st = stopped({});
    check("reboot: station 3 back, neighbours see it alive, line running",
          st.first && line_.node(1).state().next_status == 1 && line_.node(3).state().prev_status == 1,
          st.second);
  }

  /// D. Serial unplug: PC 4's cable out for 2 s; STOP2 at station 3 meanwhile.
  void unplug() {
    line_.at(15000 * kMs, [this] { line_.plug(3, false); });
    stop2(15500 * kMs, 2);
    line_.at(16500 * kMs, [this] { safe_during_outage_[1] = safe_now(3); });
    line_.at(17000 * kMs, [this] { line_.plug(3, true); });
    line_.run_until(16000 * kMs);
    check_stopped("unplug: STOP2 at station 3 stops stations 3 and 4 (gateway latch)", {2, 3});
    line_.run_until(17500 * kMs);
    check_kept_safe("unplug: PC 4 lost its link and kept its plant safe", 3, safe_during_outage_[1]);
    press(line_, 18000 * kMs, 2, gateway::kStart);
    press(line_, 18050 * kMs, 3, gateway::kStart);
    run_to(line_, 19500 * kMs, progress_, 0, 0.75, 1.0);
    check_stopped("line running again after every fault", {});
  }

  /// STOP2 never lost and never invented: each press reached its gateway's
  /// counter, its own PC and the next station's PC exactly once. A rebooted
  /// gateway shows the previous station's counter as not heard (80h in its
  /// status) until that station's TPDO1 arrives; a PC counting the 0 it
  /// showed meanwhile would see a phantom event.
  void stop2_counted_once() {
    std::string d;
    std::string extra;
    for (int k = 0; k < c_.stations; ++k) {
      const uint32_t presses = stop2_presses_[static_cast<size_t>(k)];
      const uint32_t own = plant_of(line_, k).controller().counters().local_stop2_events;
      const int nx = next_of(c_, k);
      const uint32_t next = nx < 0 ? presses : plant_of(line_, nx).controller().counters().prev_stop2_events;
      const uint32_t gw = line_.node(k).state().stop2_count;
      d += strf("%sst%d %u/%u/%u/%u", k ? ", " : "", k + 1, presses, gw, own, next);
      if (gw != presses)
        extra += strf(" gateway %d counted %u STOP2 events for %u presses;", k + 1, gw, presses);
      if (own != presses)
        extra += strf(" PC %d counted %u own STOP2 events for %u presses;", k + 1, own, presses);
      if (next != presses)
        extra += strf(" PC %d counted %u STOP2 events of station %d for %u presses;", nx + 1, next, k + 1,
                      presses);
    }
    check("STOP2 counted once everywhere (presses/gateway counter/own PC/next PC)", extra.empty(),
          extra.empty() ? d : d + ";" + extra);
  }

  /// The line's summary, and the last check that needs it: no station was
  /// unsafe without its link, overfilled or spilled.
  void safe_state_kept() {
    r_.line = summarize(line_);
    r_.line.timeline = pl_.timeline;
    bool safe = true;
    std::string sd;
    for (int i = 0; i < c_.stations; ++i) {
      const StationSummary& s = r_.line.stations[static_cast<size_t>(i)];
      safe = safe && s.unsafe_while_lost == 0 && s.overfilled == 0 && s.spilled_ul == 0;
      sd += strf("%sst%d overfilled %u spilled %llu uL", i ? ", " : "", i + 1, s.overfilled,
                 static_cast<unsigned long long>(s.spilled_ul));
    }
    check("safe state kept: no unsafe actuators without a link, no overfill, no spill", safe, sd);
  }

  FaultsResult result() {
    r_.ok = true;
    for (const FaultCheck& f : r_.checks) r_.ok = r_.ok && f.ok;
    return r_;
  }

 private:
  /// A station that has lost a neighbour's heartbeat: when, and whose.
  struct Unknown {
    SimNs t;
    int observer;
    int lost;
  };

  /// Longest pass of a plant station: it answers the 11-register read.
  static SimNs longest_plant_step_ns(const LineConfig& c) {
    uint8_t req[8];
    const uint16_t n = modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters,
                                                  pc_registers().station_first, pc_registers().station_count);
    return firmware_step_ns(c.node,
                            max_pass_ns(c.node, c.node.can_rx_buffers, 8, request_cost(c.node, req, n)));
  }

  /// Observations: last heartbeat heard from each node, neighbour-unknown times.
  void watch() {
    line_.on_can = [this](const CanAttempt& a) {
      if (!a.error && a.frame.id > 0x700 && a.frame.id <= 0x700u + static_cast<uint32_t>(c_.stations)) {
        last_hb_[a.frame.id - 0x701] = a.end_ns;
      }
    };
    auto base_state = line_.on_state;
    line_.on_state = [this, base_state](int s, const NodeState& b, const NodeState& a) {
      if (base_state) base_state(s, b, a);
      if (b.prev_status == 1 && a.prev_status == 0) unknowns_.push_back({line_.now(), s, prev_of(c_, s)});
      if (b.next_status == 1 && a.next_status == 0) unknowns_.push_back({line_.now(), s, next_of(c_, s)});
    };
  }

  void stop2(SimNs t, int k) {
    ++stop2_presses_[static_cast<size_t>(k)];
    press(line_, t, k, gateway::kStop2);
  }

  void check(const std::string& what, bool ok, const std::string& detail) {
    r_.checks.push_back({what, ok, detail});
  }

  /// Whether exactly the stations `which` are stopped (the others run), and
  /// the RUN states by station as the detail.
  std::pair<bool, std::string> stopped(std::initializer_list<int> which) {
    std::vector<bool> want(static_cast<size_t>(c_.stations), true);
    for (int i : which) want[static_cast<size_t>(i)] = false;
    std::string got;
    bool ok = true;
    for (int i = 0; i < c_.stations; ++i) {
      const bool run = line_.node(i).powered() && line_.node(i).state().run != 0;
      got += run ? "R" : "s";
      ok = ok && run == want[static_cast<size_t>(i)];
    }
    return std::make_pair(ok, "RUN by station: " + got);
  }

  void check_stopped(const std::string& what, std::initializer_list<int> which) {
    auto st = stopped(which);
    check(what, st.first, st.second);
  }

  /// Whether both neighbours of `lost` showed it unknown after `after`
  /// within the consumer time (plus a firmware step) of its last heartbeat.
  std::pair<bool, std::string> detection(int lost, SimNs after) {
    std::string d;
    bool ok = true;
    int seen = 0;
    for (int nb : {prev_of(c_, lost), next_of(c_, lost)}) {
      if (nb < 0) continue;
      SimNs at = 0;
      for (const Unknown& u : unknowns_) {
        if (u.observer == nb && u.lost == lost && u.t >= after && at == 0) at = u.t;
      }
      const SimNs delay = at == 0 ? 0 : at - last_hb_[static_cast<size_t>(lost)];
      ok = ok && at != 0 && delay <= consumer_ns_ + step_ns_;
      d += strf("%sstation %d: %s", seen++ ? ", " : "", nb + 1,
                at == 0 ? "never"
                        : strf("%.1f ms after the last heartbeat", static_cast<double>(delay) / 1e6).c_str());
    }
    return std::make_pair(ok, d + strf(" (consumer time %llu ms, +%.1f ms firmware step)",
                                       static_cast<unsigned long long>(consumer_ns_ / kMs),
                                       static_cast<double>(step_ns_) / 1e6));
  }

  /// Station `s`'s PC keeps its plant safe: stopped, motor off, valve closed.
  bool safe_now(int s) {
    const PlantProgram& p = plant_of(line_, s);
    const plant::Actuators& a = p.controller().outputs().plant;
    return !p.controller().running() && !a.motor_on && !a.valve_open;
  }

  /// PC `s` lost its link during the outage and was safe in the middle of it.
  void check_kept_safe(const std::string& what, int s, bool safe_mid_outage) {
    check(what, safe_mid_outage && plant_of(line_, s).link_losses() > 0,
          strf("link losses %llu, safe mid-outage: %s",
               static_cast<unsigned long long>(plant_of(line_, s).link_losses()),
               safe_mid_outage ? "yes" : "no"));
  }

  const LineConfig& c_;
  const Progress& progress_;
  PlantLine pl_;
  Line& line_;
  const SimNs consumer_ns_;
  const SimNs step_ns_;
  std::vector<SimNs> last_hb_;
  std::vector<Unknown> unknowns_;
  std::vector<uint32_t> stop2_presses_;
  bool safe_during_outage_[2] = {false, false};  ///< PC 3 in the reboot, PC 4 in the unplug
  FaultsResult r_;
};

}  // namespace

FaultsResult faults_scenario(const LineConfig& c, EventLog* log, const Progress& progress) {
  if (c.stations < 4) {
    FaultsResult r;
    r.checks.push_back({"at least 4 stations", false, "the faults scenario needs stations 1..4"});
    return r;
  }
  FaultsRun run(c, log, progress);
  run.running_before_the_faults();
  run.frame_loss();
  run.bus_off();
  run.reboot();
  run.unplug();
  run.stop2_counted_once();
  run.safe_state_kept();
  return run.result();
}

}  // namespace sim
}  // namespace mb2co
