// Pieces the scenario runners share (scenarios.cpp, faults_scenario.cpp):
// a plant line with its operator, button presses, progress, neighbours and
// the LEDs a set of RUN states should light. Internal to hil/sim.
#pragma once
#include <algorithm>
#include <memory>
#include <vector>

#include "gateway/line_app.h"
#include "sim/line.h"
#include "sim/pc_programs.h"
#include "sim/timeline.h"

namespace mb2co {
namespace sim {
namespace scenario_parts {

constexpr SimNs kMs = kNsPerMs;
constexpr SimNs kS = kNsPerS;
enum : uint64_t { kStreamOperator = 700 };

inline plant::PlantConfig plant_config(const LineConfig& c) {
  plant::PlantConfig p;
  p.step_ms = static_cast<uint32_t>(c.pc.cycle_ns / kMs);
  return p;
}

inline PlantProgram& plant_of(Line& line, int i) {
  return *static_cast<PlantProgram*>(line.pc(i).program());
}

inline void install_plants(Line& line) {
  for (int i = 0; i < line.size(); ++i) {
    line.pc(i).set_program(std::unique_ptr<PcProgram>(new PlantProgram(plant_config(line.config()), 1)));
  }
}

inline void start_all(Line& line) {
  line.power_on_all();
  for (int i = 0; i < line.size(); ++i) {
    if (line.pc(i).program() != nullptr) line.pc(i).start();
  }
}

inline void press(Line& line, SimNs t, int station, uint8_t button, SimNs hold = 100 * kMs) {
  line.at(t, [&line, station, button] { line.set_button(station, button, true); });
  line.at(t + hold, [&line, station, button] { line.set_button(station, button, false); });
}

inline void record_timeline(Line& line, std::vector<TimelineEvent>& tl) {
  line.on_state = [&line, &tl](int s, const NodeState& b, const NodeState& a) {
    if (a.run != b.run) tl.push_back({line.now(), s, a.run ? TimelineEvent::kRun : TimelineEvent::kStop});
  };
  line.on_button = [&line, &tl](int s, uint8_t button, bool pressed) {
    if (!pressed) return;
    if (button == gateway::kStop2) tl.push_back({line.now(), s, TimelineEvent::kStop2Press});
    if (button == gateway::kStart) tl.push_back({line.now(), s, TimelineEvent::kStartPress});
  };
}

/// Runs to `end` in 1-second slices, reporting progress in [from, to].
inline void run_to(Line& line, SimNs end, const Progress& progress, SimNs origin, double from, double to) {
  while (line.now() < end) {
    const SimNs next = std::min(end, line.now() + kS);
    line.run_until(next);
    if (progress && end > origin) {
      progress(from +
               (to - from) * static_cast<double>(line.now() - origin) / static_cast<double>(end - origin));
    }
  }
}

inline int prev_of(const LineConfig& c, int j) {
  return j > 0 ? j - 1 : (c.ring ? c.stations - 1 : -1);
}
inline int next_of(const LineConfig& c, int j) {
  return j + 1 < c.stations ? j + 1 : (c.ring ? 0 : -1);
}

/// RUN-self, RUN-prev, RUN-next LED bits for `running` states.
inline uint8_t expected_leds(const LineConfig& c, const std::vector<bool>& running, int j) {
  uint8_t leds = running[static_cast<size_t>(j)] ? gateway::kLedRunSelf : 0;
  const int p = prev_of(c, j);
  const int n = next_of(c, j);
  if (p >= 0 && running[static_cast<size_t>(p)]) leds |= gateway::kLedRunPrev;
  if (n >= 0 && running[static_cast<size_t>(n)]) leds |= gateway::kLedRunNext;
  return leds;
}

inline bool all_running(Line& line) {
  for (int i = 0; i < line.size(); ++i) {
    if (line.node(i).state().run == 0) return false;
  }
  return true;
}

inline bool leds_match(Line& line, const std::vector<bool>& running) {
  for (int i = 0; i < line.size(); ++i) {
    if ((line.node(i).leds() & 0x07) != expected_leds(line.config(), running, i)) return false;
  }
  return true;
}

/// A line whose PCs run their plants, with an operator and a timeline.
struct PlantLine {
  PlantLine(const LineConfig& c, EventLog* log, const char* run)
      : line(c, log), rng(mix_seed(c.seed, kStreamOperator)) {
    if (log) log->set_run(run);
    install_plants(line);
    record_timeline(line, timeline);
  }
  Line line;
  Rng rng;
  std::vector<TimelineEvent> timeline;
};

/// Power on, START on every station at about 1 s, run to 3 s.
inline void bring_up(Line& line, Rng& rng, const Progress& progress, double to) {
  start_all(line);
  for (int i = 0; i < line.size(); ++i) press(line, kS + rng.range(0, 200 * kMs), i, gateway::kStart);
  run_to(line, 3 * kS, progress, 0, 0, to);
}

}  // namespace scenario_parts
}  // namespace sim
}  // namespace mb2co
