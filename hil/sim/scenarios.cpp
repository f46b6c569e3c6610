#include "sim/scenarios.h"

#include "sim/press_loop.h"
#include "sim/scenario_parts.h"
#include "sim/worst_presses.h"

namespace mb2co {
namespace sim {

using namespace scenario_parts;

LineSummary summarize(Line& line) {
  LineSummary s;
  for (int i = 0; i < line.size(); ++i) {
    StationSummary st;
    NodeStation& n = line.node(i);
    st.running = n.powered() && n.state().run != 0;
    st.leds = n.leds();
    st.passes = n.passes();
    st.pc_cycles = line.pc(i).counters().cycles;
    st.pc_overruns = line.pc(i).counters().overruns;
    st.pc_failures = line.pc(i).counters().failures;
    if (auto* p = dynamic_cast<PlantProgram*>(line.pc(i).program())) {
      st.bottles_filled = p->controller().counters().bottles_filled;
      st.handed_off = p->plant().counters().handed_off;
      st.overfilled = p->plant().counters().overfilled;
      st.spilled_ul = p->plant().counters().spilled_ul;
      st.local_stop2_seen = p->controller().counters().local_stop2_events;
      st.prev_stop2_seen = p->controller().counters().prev_stop2_events;
      st.unsafe_while_lost = p->unsafe_while_lost();
      st.link_losses = p->link_losses();
    }
    s.rx_overflows += n.can().counters().rx_overflows;
    s.stations.push_back(st);
  }
  s.can_frames = line.bus().frames_ok();
  s.error_frames = line.bus().error_frames();
  s.ack_error_frames = line.bus().ack_error_frames();
  s.duration_ns = line.now();
  s.bus_load =
      line.now() == 0 ? 0 : static_cast<double>(line.bus().busy_ns()) / static_cast<double>(line.now());
  s.events = line.queue().handled();
  return s;
}

// ---- run -------------------------------------------------------------------

RunResult run_scenario(const LineConfig& c, SimNs duration_ns, EventLog* log, const Progress& progress) {
  RunResult r;
  PlantLine pl(c, log, "run");
  Line& line = pl.line;
  Rng& rng = pl.rng;
  const std::vector<TimelineEvent>& tl = pl.timeline;
  const SimNs end = std::max(duration_ns, 4 * kS);
  bring_up(line, rng, progress, static_cast<double>(3 * kS) / static_cast<double>(end));
  run_to(line, end, progress, 0, 0, 1);
  r.all_running = all_running(line);
  r.leds_ok = leds_match(line, std::vector<bool>(static_cast<size_t>(line.size()), true));
  r.line = summarize(line);
  r.line.timeline = tl;
  r.ok = r.all_running && r.leds_ok;
  for (const StationSummary& s : r.line.stations)
    r.ok = r.ok && s.bottles_filled > 0 && s.overfilled == 0 && s.spilled_ul == 0;
  return r;
}

uint32_t run_min_duration_s(const LineConfig& c) {
  const plant::PlantConfig p = plant_config(c);
  const uint64_t start_ms = 1200;
  const uint64_t travel_ms = 1000ull * p.valve_position_mm / p.conveyor_speed_mm_s;
  const uint64_t fill_ms = 1000ull * p.fill_level_ml / p.fill_flow_ml_s;
  return static_cast<uint32_t>((start_ms + travel_ms + fill_ms + 1000 + 999) / 1000);
}

// ---- stop2 -----------------------------------------------------------------

Stop2Result stop2_scenario(const LineConfig& c, EventLog* log, const Progress& progress) {
  Stop2Result r;
  PlantLine pl(c, log, "stop2");
  Line& line = pl.line;
  Rng& rng = pl.rng;
  const std::vector<TimelineEvent>& tl = pl.timeline;
  const double per_case = 1.0 / (c.stations + 1);
  bring_up(line, rng, progress, per_case);
  const bool up = all_running(line);

  // LED changes after a press: first time the RUN-self LED of a station went off.
  SimNs pressed_at = 0;
  std::vector<SimNs> self_off(static_cast<size_t>(c.stations), 0);
  line.on_leds = [&](int s, uint8_t leds) {
    if (pressed_at != 0 && !(leds & gateway::kLedRunSelf) && self_off[static_cast<size_t>(s)] == 0) {
      self_off[static_cast<size_t>(s)] = line.now() - pressed_at;
    }
  };
  for (int k = 0; k < c.stations; ++k) {
    Stop2Case sc;
    sc.k = k;
    const SimNs t = line.now() + 500 * kMs + rng.range(0, 50 * kMs);
    std::fill(self_off.begin(), self_off.end(), 0);
    line.run_until(t);
    pressed_at = t;
    line.set_button(k, gateway::kStop2, true);
    line.at(t + 100 * kMs, [&line, k] { line.set_button(k, gateway::kStop2, false); });
    line.run_until(t + 400 * kMs);
    sc.expected.push_back(k);
    if (next_of(c, k) >= 0) sc.expected.push_back(next_of(c, k));
    std::sort(sc.expected.begin(), sc.expected.end());
    std::vector<bool> running(static_cast<size_t>(c.stations), true);
    for (int i = 0; i < c.stations; ++i) {
      if (line.node(i).state().run == 0) sc.stopped.push_back(i);
    }
    for (int i : sc.expected) running[static_cast<size_t>(i)] = false;
    sc.leds_ok = true;
    for (int j = k - 1; j <= k + 2; ++j) {
      const int s = c.ring ? (j + c.stations) % c.stations : j;
      if (s < 0 || s >= c.stations) continue;
      const uint8_t want = expected_leds(c, running, s);
      const uint8_t got = line.node(s).leds() & 0x07;
      if (want != got) {
        sc.leds_ok = false;
        sc.led_errors.push_back(strf("station %d LEDs %X, want %X", s + 1, got, want));
      }
    }
    sc.own_led_ns = self_off[static_cast<size_t>(k)];
    if (next_of(c, k) >= 0) sc.next_led_ns = self_off[static_cast<size_t>(next_of(c, k))];
    pressed_at = 0;
    // The operator restarts the stopped stations.
    for (int i : sc.expected) press(line, t + 600 * kMs + rng.range(0, 100 * kMs), i, gateway::kStart);
    run_to(line, t + 1700 * kMs, nullptr, 0, 0, 0);
    sc.restarted = all_running(line);
    sc.ok = up && sc.stopped == sc.expected && sc.leds_ok && sc.own_led_ns != 0 && sc.restarted;
    r.cases.push_back(sc);
    if (progress) progress(per_case * (k + 2));
  }
  r.line = summarize(line);
  r.line.timeline = tl;
  r.ok = up;
  for (const Stop2Case& sc : r.cases) r.ok = r.ok && sc.ok;
  return r;
}

// ---- latency ---------------------------------------------------------------

LatencyResult latency_scenario(LineConfig c, const LatencyCase& lc, uint32_t presses, EventLog* log,
                               const Progress& progress) {
  LatencyResult r;
  r.c = lc;
  if (c.lab_pc < 0) {
    c.lab_pc = 0;
    c.lab_remote = 1;
  }
  c.bitrate_kbit = lc.bitrate_kbit;
  if (log) {
    log->set_run(strf("latency-%uk-%s%s", lc.bitrate_kbit, lc.remote ? "canopen" : "modbus",
                      lc.worst ? "-worst" : ""));
  }
  Line line(c, log);
  line.pc(c.lab_pc).set_program(std::unique_ptr<PcProgram>(new LabProgram(1, lc.remote)));
  line.power_on_all();
  line.pc(c.lab_pc).start();

  const int station = lc.remote ? c.lab_remote : c.lab_pc;  // button and LED
  Rng rng(mix_seed(c.seed, kStreamOperator + 1 + lc.bitrate_kbit * 2 + (lc.remote ? 1 : 0)));
  const uint32_t up_id = 0x280u + static_cast<uint32_t>(c.lab_remote + 1);
  const uint32_t down_id = 0x380u + static_cast<uint32_t>(c.lab_pc + 1);
  for (int i = 0; i < line.size(); ++i) {
    auto logged = line.node(i).can().on_overflow;
    line.node(i).can().on_overflow = [&r, logged, up_id, down_id](const CanFrame& f) {
      if (logged) logged(f);
      if (f.id == up_id || f.id == down_id) ++r.lab_frames_lost;
    };
  }
  PressRun presses_run = lc.worst ? search_worst_presses(line, station, station, lc.remote, progress)
                                  : run_presses(line, station, station, presses, rng, progress);
  r.samples_ns = std::move(presses_run.samples_ns);
  r.lost = presses_run.lost;

  LabOperator op;
  op.interference = lc.worst && lc.remote;   // what search_worst_presses presses besides the lab button
  r.bound = lab_bound(line, lc.remote, op);  // every Arduino is up by now
  r.duration_ns = line.now();
  r.events = line.queue().handled();
  for (int i = 0; i < line.size(); ++i) r.rx_overflows += line.node(i).can().counters().rx_overflows;
  r.t15_discards = line.node(c.lab_pc).gateway().modbus_slave().stats().t15_violations;
  judge_latency(r);
  return r;
}

}  // namespace sim
}  // namespace mb2co
