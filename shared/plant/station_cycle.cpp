#include "plant/station_cycle.h"

#include "gateway/line_values.h"

namespace mb2co {
namespace plant {

const Field kStationReads[kStationReadCount] = {Field::kInputs,     Field::kRunState, Field::kStop2Count,
                                                Field::kStopCause,  Field::kPrevRun,  Field::kPrevStop2,
                                                Field::kPrevStatus, Field::kNextRun,  Field::kNextStatus};
const Field kStationOptionalReads[kStationOptionalReadCount] = {
    Field::kLeds, Field::kStartCount, Field::kStopCount, Field::kErrorRegister, Field::kNmtState};

NeighbourState neighbour_state(uint8_t status, uint8_t run) {
  switch (status) {
    case gateway::kNeighbourAlive:
      return run != 0 ? NeighbourState::kRunning : NeighbourState::kStopped;
    case gateway::kNeighbourNone:
      return NeighbourState::kAbsent;
    default:
      // Lost, not heard since the gateway's reset (kNeighbourNotHeard), or a
      // status we do not know: never "running".
      return NeighbourState::kUnknown;
  }
}

ControllerInputs controller_inputs(const Panel& panel, bool run_confirmed, const Sensors& sensors) {
  ControllerInputs in;
  in.start_pressed = (panel.buttons & gateway::kStart) != 0;
  const bool latched_stop =
      run_confirmed && panel.run_state == 0 && panel.stop_cause == reported_cause(StopCause::kStopButton);
  in.stop_pressed = (panel.buttons & gateway::kStop) != 0 || latched_stop;
  in.stop2_pressed = (panel.buttons & gateway::kStop2) != 0;
  in.local_stop2_events = panel.stop2_count;
  in.prev_stop2_events = panel.prev_stop2;
  in.prev_stop2_known = (panel.prev_status & gateway::kNeighbourNotHeard) == 0;
  in.prev_run = neighbour_state(panel.prev_status, panel.prev_run);
  in.next_run = neighbour_state(panel.next_status, panel.next_run);
  in.plant = sensors;
  return in;
}

StationCycle::StationCycle(const PlantConfig& config)
    : plant_(config), controller_(controller_config_for(config)) {}

bool StationCycle::step(const Panel& panel) {
  panel_ = panel;
  panel_known_ = true;
  const bool confirmed = run_written_[0] && run_written_[1];
  const ControllerOutputs& o = controller_.step(controller_inputs(panel_, confirmed, plant_.sensors()));
  plant_.step(o.plant);
  run_written_[1] = run_written_[0];
  run_written_[0] = o.run == RunState::kRunning;
  return run_written_[0];
}

void StationCycle::step_offline() {
  plant_.step(controller_.outputs().plant);
}

void StationCycle::link_lost() {
  controller_.force_safe();
  run_written_[0] = run_written_[1] = false;
  panel_known_ = false;
}

}  // namespace plant
}  // namespace mb2co
