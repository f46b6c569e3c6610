#include "station_cycle.h"

#include "gateway/line_app.h"

namespace mb2co {
namespace pcapp {

using plant::State;
using plant::StopCause;

const char* state_name(State state) {
  switch (state) {
    case State::kStopped:
      return "stopped";
    case State::kFault:
      return "fault";
    case State::kMoving:
      return "moving";
    case State::kApproach:
      return "approach";
    case State::kFilling:
      return "filling";
  }
  return "?";
}

const char* stop_cause_name(StopCause cause) {
  switch (cause) {
    case StopCause::kStopButton:
      return "stop_button";
    case StopCause::kLocalStop2:
      return "local_stop2";
    case StopCause::kPrevStop2:
      return "prev_stop2";
    case StopCause::kLinkLost:
      return "link_lost";
    case StopCause::kFault:
      return "fault";
  }
  return "?";
}

namespace {
const char* fault_name(plant::Fault f) {
  switch (f) {
    case plant::Fault::kNone:
      return "none";
    case plant::Fault::kFillTimeout:
      return "fill_timeout";
    case plant::Fault::kBottleLost:
      return "bottle_lost";
    case plant::Fault::kOverfill:
      return "overfill";
  }
  return "?";
}

std::string buttons_text(uint8_t buttons) {
  std::string s;
  if (buttons & gateway::kStart) s += "START ";
  if (buttons & gateway::kStop) s += "STOP ";
  if (buttons & gateway::kStop2) s += "STOP2 ";
  if (s.empty()) return "none";
  s.pop_back();
  return s;
}

const char* neighbour_name(plant::NeighbourState s) {
  switch (s) {
    case plant::NeighbourState::kAbsent:
      return "none";
    case plant::NeighbourState::kUnknown:
      return "unknown";
    case plant::NeighbourState::kStopped:
      return "stopped";
    case plant::NeighbourState::kRunning:
      return "running";
  }
  return "?";
}
}  // namespace

StationCycle::StationCycle(const RegisterLayout& layout, const plant::PlantConfig& config)
    : layout_(layout), cycle_(config) {}

std::vector<Field> StationCycle::required_reads() const {
  return {plant::kStationReads, plant::kStationReads + plant::kStationReadCount};
}

std::vector<Field> StationCycle::optional_reads() const {
  return {plant::kStationOptionalReads, plant::kStationOptionalReads + plant::kStationOptionalReadCount};
}

void StationCycle::step(const RegisterImage& in, RegisterImage& out) {
  const uint8_t buttons_before = cycle_.panel().buttons;
  const bool known_before = cycle_.panel_known();
  const plant::ControllerCounters before = cycle_.controller().counters();
  const State state_before = cycle_.controller().state();
  const bool run = cycle_.step(decode_panel(layout_, in));
  if (!known_before || cycle_.panel().buttons != buttons_before) {
    event_ = "buttons " + buttons_text(cycle_.panel().buttons);
  }
  out.put(layout_, Field::kRunCommand, run ? 1u : 0u);
  note_changes(before, state_before);
}

void StationCycle::step_offline() {
  cycle_.step_offline();
}

void StationCycle::link_lost() {
  const plant::ControllerCounters before = cycle_.controller().counters();
  const State state_before = cycle_.controller().state();
  cycle_.link_lost();
  note_changes(before, state_before);
}

void StationCycle::safe_outputs(RegisterImage& out) const {
  out.put(layout_, Field::kRunCommand, 0);
}

void StationCycle::note_changes(const plant::ControllerCounters& before, State state_before) {
  const State now = controller().state();
  if (now == state_before) return;
  if (!event_.empty()) event_ += '\n';
  event_ += std::string("state ") + state_name(now);
  for (uint8_t c = 0; c < plant::kStopCauseCount; ++c) {
    if (controller().counters().stops[c] != before.stops[c]) {
      event_ += std::string(" cause=") + stop_cause_name(static_cast<StopCause>(c));
      break;
    }
  }
  if (now == State::kFault) event_ += std::string(" fault=") + fault_name(controller().fault());
}

std::string StationCycle::take_event() {
  std::string e;
  e.swap(event_);
  return e;
}

std::string StationCycle::status() const {
  const plant::Sensors s = plant().sensors();
  const plant::ControllerInputs in = controller_inputs(panel(), false, s);
  std::string line = std::string("station ") + state_name(controller().state());
  line += std::string(" | prev ") + neighbour_name(in.prev_run) + " next " + neighbour_name(in.next_run);
  line += " | bottles filled " + std::to_string(controller().counters().bottles_filled) + " out " +
          std::to_string(plant().counters().handed_off) + " | level " + std::to_string(s.level_ml) + " mL";
  line += " | buttons " + buttons_text(panel().buttons);
  return line;
}

std::vector<const char*> StationCycle::column_names() const {
  return {"buttons", "run_state", "stop_cause",  "stop2_count", "prev_stop2", "prev",
          "next",    "leds",      "run_command", "state",       "motor",      "valve",
          "bottle",  "level_ml",  "filled",      "handed_off",  "spilled_ul"};
}

void StationCycle::columns(std::vector<LogValue>& out) const {
  const plant::Sensors s = plant().sensors();
  const plant::ControllerOutputs& o = controller().outputs();
  auto n = [&](int64_t v) { out.push_back(LogValue{v, nullptr}); };
  auto t = [&](const char* v) { out.push_back(LogValue{0, v}); };
  n(panel().buttons);
  n(panel().run_state);
  n(panel().stop_cause);
  n(panel().stop2_count);
  n(panel().prev_stop2);
  t(neighbour_name(neighbour_state(panel().prev_status, panel().prev_run)));
  t(neighbour_name(neighbour_state(panel().next_status, panel().next_run)));
  n(panel().leds);
  n(cycle_.run_command() ? 1 : 0);
  t(state_name(controller().state()));
  n(o.plant.motor_on ? 1 : 0);
  n(o.plant.valve_open ? 1 : 0);
  n(s.bottle_present ? 1 : 0);
  n(s.level_ml);
  n(controller().counters().bottles_filled);
  n(plant().counters().handed_off);
  n(static_cast<int64_t>(plant().counters().spilled_ul));
}

std::string StationCycle::summary() const {
  const plant::ControllerCounters& c = controller().counters();
  const plant::PlantCounters& p = plant().counters();
  std::string s = "starts=" + std::to_string(c.starts) + " filled=" + std::to_string(c.bottles_filled) +
                  " handed_off=" + std::to_string(p.handed_off) +
                  " overfilled=" + std::to_string(p.overfilled) +
                  " spilled_ul=" + std::to_string(p.spilled_ul) + " stops:";
  for (uint8_t k = 0; k < plant::kStopCauseCount; ++k) {
    s += std::string(" ") + stop_cause_name(static_cast<StopCause>(k)) + "=" + std::to_string(c.stops[k]);
  }
  return s;
}

}  // namespace pcapp
}  // namespace mb2co
