#include "modbus/master_codec.h"
#include "sim/scenario_parts.h"

namespace mb2co {
namespace sim {

using namespace scenario_parts;

// ---- faults ----------------------------------------------------------------

FaultsResult faults_scenario(const LineConfig& c, EventLog* log, const Progress& progress) {
  FaultsResult r;
  if (c.stations < 4) {
    r.checks.push_back({"at least 4 stations", false, "the faults scenario needs stations 1..4"});
    return r;
  }
  PlantLine pl(c, log, "faults");
  Line& line = pl.line;
  Rng& rng = pl.rng;
  const std::vector<TimelineEvent>& tl = pl.timeline;
  const SimNs consumer_ns = 3u * c.heartbeat_ms * kMs;
  // Longest pass of a plant station: it answers the 11-register read.
  uint8_t req[8];
  const uint16_t n = modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters,
                                                pc_registers().station_first, pc_registers().station_count);
  const SimNs step_ns =
      firmware_step_ns(c.node, max_pass_ns(c.node, c.node.can_rx_buffers, 8, request_cost(c.node, req, n)));

  // Observations: last heartbeat heard from each node, neighbour-unknown times.
  std::vector<SimNs> last_hb(static_cast<size_t>(c.stations), 0);
  struct Unknown {
    SimNs t;
    int observer;
    int lost;
  };
  std::vector<Unknown> unknowns;
  line.on_can = [&](const CanAttempt& a) {
    if (!a.error && a.frame.id > 0x700 && a.frame.id <= 0x700u + static_cast<uint32_t>(c.stations)) {
      last_hb[a.frame.id - 0x701] = a.end_ns;
    }
  };
  auto base_state = line.on_state;
  line.on_state = [&, base_state](int s, const NodeState& b, const NodeState& a) {
    if (base_state) base_state(s, b, a);
    if (b.prev_status == 1 && a.prev_status == 0) unknowns.push_back({line.now(), s, prev_of(c, s)});
    if (b.next_status == 1 && a.next_status == 0) unknowns.push_back({line.now(), s, next_of(c, s)});
  };
  std::vector<uint32_t> stop2_presses(static_cast<size_t>(c.stations), 0);
  auto stop2 = [&](SimNs t, int k) {
    ++stop2_presses[static_cast<size_t>(k)];
    press(line, t, k, gateway::kStop2);
  };
  auto check = [&](const std::string& what, bool ok, const std::string& detail) {
    r.checks.push_back({what, ok, detail});
  };
  auto stopped = [&](std::initializer_list<int> which) {
    std::vector<bool> want(static_cast<size_t>(c.stations), true);
    for (int i : which) want[static_cast<size_t>(i)] = false;
    std::string got;
    bool ok = true;
    for (int i = 0; i < c.stations; ++i) {
      const bool run = line.node(i).powered() && line.node(i).state().run != 0;
      got += run ? "R" : "s";
      ok = ok && run == want[static_cast<size_t>(i)];
    }
    return std::make_pair(ok, "RUN by station: " + got);
  };
  auto detection = [&](int lost, SimNs after) {
    std::string d;
    bool ok = true;
    int seen = 0;
    for (int nb : {prev_of(c, lost), next_of(c, lost)}) {
      if (nb < 0) continue;
      SimNs at = 0;
      for (const Unknown& u : unknowns) {
        if (u.observer == nb && u.lost == lost && u.t >= after && at == 0) at = u.t;
      }
      const SimNs delay = at == 0 ? 0 : at - last_hb[static_cast<size_t>(lost)];
      ok = ok && at != 0 && delay <= consumer_ns + step_ns;
      d += strf("%sstation %d: %s", seen++ ? ", " : "", nb + 1,
                at == 0 ? "never"
                        : strf("%.1f ms after the last heartbeat", static_cast<double>(delay) / 1e6).c_str());
    }
    return std::make_pair(
        ok, d + strf(" (consumer time %llu ms, +%.1f ms firmware step)",
                     static_cast<unsigned long long>(consumer_ns / kMs), static_cast<double>(step_ns) / 1e6));
  };
  bool safe_during_outage[2] = {false, false};
  auto safe_now = [&](int s) {
    const PlantProgram& p = plant_of(line, s);
    const plant::Actuators& a = p.controller().outputs().plant;
    return !p.controller().running() && !a.motor_on && !a.valve_open;
  };

  bring_up(line, rng, progress, 0.15);
  {
    auto st = stopped({});
    check("line running before the faults", st.first, st.second);
  }

  // A. Frame loss: 2 % of frames destroyed (error frame, retransmission).
  const uint64_t errors_before = line.bus().error_frames();
  line.at(3500 * kMs, [&] {
    line.note(-1, "fault", "corruption ppm=20000");
    line.bus().set_corruption_ppm(20000);
  });
  stop2(4000 * kMs, 0);
  line.run_until(4500 * kMs);
  {
    auto st = stopped({0, 1});
    check("frame loss: STOP2 at station 1 stops stations 1 and 2", st.first, st.second);
  }
  press(line, 5000 * kMs, 0, gateway::kStart);
  press(line, 5050 * kMs, 1, gateway::kStart);
  line.at(6500 * kMs, [&] {
    line.note(-1, "fault", "corruption ppm=0");
    line.bus().set_corruption_ppm(0);
  });
  run_to(line, 7000 * kMs, progress, 0, 0.15, 0.35);
  check("frame loss: error frames seen and retransmitted",
        line.bus().error_frames() > errors_before && stopped({}).first,
        strf("%llu error frames, line running again: %s",
             static_cast<unsigned long long>(line.bus().error_frames() - errors_before),
             stopped({}).first ? "yes" : "no"));

  // B. Bus-off: station 2's transceiver destroys every frame it sends for 2 s.
  const SimNs b0 = 7000 * kMs;
  line.at(b0, [&] {
    line.note(1, "fault", "tx broken");
    line.node(1).can().set_tx_broken(true);
  });
  stop2(7500 * kMs, 1);
  line.at(9000 * kMs, [&] {
    line.note(1, "fault", "tx repaired");
    line.node(1).can().set_tx_broken(false);
  });
  line.run_until(8600 * kMs);
  {
    auto d = detection(1, b0);
    check("bus-off: station 2 went bus-off", line.node(1).can().counters().bus_offs > 0,
          strf("%llu bus-off entries",
               static_cast<unsigned long long>(line.node(1).can().counters().bus_offs)));
    check("bus-off: neighbours show station 2 unknown within the consumer time", d.first, d.second);
    auto st = stopped({1});
    check("bus-off: STOP2 at station 2 stops it at once (station 3 not told yet)", st.first, st.second);
  }
  line.run_until(9800 * kMs);
  {
    auto st = stopped({1, 2});
    check("bus-off: after recovery the STOP2 reaches station 3", st.first, st.second);
  }
  press(line, 10000 * kMs, 1, gateway::kStart);
  press(line, 10050 * kMs, 2, gateway::kStart);
  run_to(line, 11000 * kMs, progress, 0, 0.35, 0.55);

  // C. Neighbour reboot: station 3 powered off for 1 s.
  const SimNs c0 = 11500 * kMs;
  line.at(c0, [&] { line.power(2, false); });
  line.at(12000 * kMs, [&] { safe_during_outage[0] = safe_now(2); });
  line.at(12500 * kMs, [&] { line.power(2, true); });
  line.run_until(12500 * kMs);
  {
    auto d = detection(2, c0);
    check("reboot: neighbours show station 3 unknown within the consumer time", d.first, d.second);
    check("reboot: PC 3 lost its link and kept its plant safe",
          safe_during_outage[0] && plant_of(line, 2).link_losses() > 0,
          strf("link losses %llu, safe mid-outage: %s",
               static_cast<unsigned long long>(plant_of(line, 2).link_losses()),
               safe_during_outage[0] ? "yes" : "no"));
  }
  press(line, 13500 * kMs, 2, gateway::kStart);
  run_to(line, 14500 * kMs, progress, 0, 0.55, 0.75);
  {
    auto st = stopped({});
    check("reboot: station 3 back, neighbours see it alive, line running",
          st.first && line.node(1).state().next_status == 1 && line.node(3).state().prev_status == 1,
          st.second);
  }

  // D. Serial unplug: PC 4's cable out for 2 s; STOP2 at station 3 meanwhile.
  line.at(15000 * kMs, [&] { line.plug(3, false); });
  stop2(15500 * kMs, 2);
  line.at(16500 * kMs, [&] { safe_during_outage[1] = safe_now(3); });
  line.at(17000 * kMs, [&] { line.plug(3, true); });
  line.run_until(16000 * kMs);
  {
    auto st = stopped({2, 3});
    check("unplug: STOP2 at station 3 stops stations 3 and 4 (gateway latch)", st.first, st.second);
  }
  line.run_until(17500 * kMs);
  check("unplug: PC 4 lost its link and kept its plant safe",
        safe_during_outage[1] && plant_of(line, 3).link_losses() > 0,
        strf("link losses %llu, safe mid-outage: %s",
             static_cast<unsigned long long>(plant_of(line, 3).link_losses()),
             safe_during_outage[1] ? "yes" : "no"));
  press(line, 18000 * kMs, 2, gateway::kStart);
  press(line, 18050 * kMs, 3, gateway::kStart);
  run_to(line, 19500 * kMs, progress, 0, 0.75, 1.0);
  {
    auto st = stopped({});
    check("line running again after every fault", st.first, st.second);
  }

  // STOP2 never lost and never invented: each press reached its gateway's
  // counter, its own PC and the next station's PC exactly once. A rebooted
  // gateway shows the previous station's counter as not heard (80h in its
  // status) until that station's TPDO1 arrives; a PC counting the 0 it
  // showed meanwhile would see a phantom event.
  std::string d;
  std::string extra;
  for (int k = 0; k < c.stations; ++k) {
    const uint32_t presses = stop2_presses[static_cast<size_t>(k)];
    const uint32_t own = plant_of(line, k).controller().counters().local_stop2_events;
    const int nx = next_of(c, k);
    const uint32_t next = nx < 0 ? presses : plant_of(line, nx).controller().counters().prev_stop2_events;
    const uint32_t gw = line.node(k).state().stop2_count;
    d += strf("%sst%d %u/%u/%u/%u", k ? ", " : "", k + 1, presses, gw, own, next);
    if (gw != presses)
      extra += strf(" gateway %d counted %u STOP2 events for %u presses;", k + 1, gw, presses);
    if (own != presses)
      extra += strf(" PC %d counted %u own STOP2 events for %u presses;", k + 1, own, presses);
    if (next != presses)
      extra +=
          strf(" PC %d counted %u STOP2 events of station %d for %u presses;", nx + 1, next, k + 1, presses);
  }
  check("STOP2 counted once everywhere (presses/gateway counter/own PC/next PC)", extra.empty(),
        extra.empty() ? d : d + ";" + extra);
  r.line = summarize(line);
  r.line.timeline = tl;
  bool safe = true;
  std::string sd;
  for (int i = 0; i < c.stations; ++i) {
    const StationSummary& s = r.line.stations[static_cast<size_t>(i)];
    safe = safe && s.unsafe_while_lost == 0 && s.overfilled == 0 && s.spilled_ul == 0;
    sd += strf("%sst%d overfilled %u spilled %llu uL", i ? ", " : "", i + 1, s.overfilled,
               static_cast<unsigned long long>(s.spilled_ul));
  }
  check("safe state kept: no unsafe actuators without a link, no overfill, no spill", safe, sd);
  r.ok = true;
  for (const FaultCheck& f : r.checks) r.ok = r.ok && f.ok;
  return r;
}

}  // namespace sim
}  // namespace mb2co
