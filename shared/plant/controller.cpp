#include "plant/controller.h"

namespace mb2co {
namespace plant {

ControllerConfig controller_config_for(const PlantConfig& config) {
  ControllerConfig c;
  c.approach_steps = approach_steps(config);
  c.fill_timeout_steps = fill_timeout_steps(config);
  c.sensor_at_valve = config.sensor_to_valve_mm == 0u;
  return c;
}

Controller::Controller(const ControllerConfig& config) : config_(config) {
  update_outputs();
}

const ControllerOutputs& Controller::step(const ControllerInputs& in) {
  // Sample every edge and counter every cycle, so none is lost or invented
  // whatever state the controller is in.
  const uint16_t local_events = local_stop2_.update(in.local_stop2_events);
  const uint16_t prev_events = in.prev_stop2_known ? prev_stop2_.update(in.prev_stop2_events) : 0u;
  counters_.local_stop2_events += local_events;
  counters_.prev_stop2_events += prev_events;
  const bool start_edge = start_.update(in.start_pressed);
  const bool present_edge = present_.update(in.plant.bottle_present);
  const bool overfill_edge = overfill_.update(in.plant.overfill);
  if (overfill_edge) ++counters_.overfills;

  // Priority when several come together: the station's own STOP first.
  bool stop_requested = true;
  StopCause cause = StopCause::kStopButton;
  if (in.stop_pressed) {
    cause = StopCause::kStopButton;
  } else if (in.stop2_pressed || local_events != 0u) {
    cause = StopCause::kLocalStop2;
  } else if (prev_events != 0u) {
    cause = StopCause::kPrevStop2;
  } else {
    stop_requested = false;
  }

  if (running()) {
    if (stop_requested) {
      stop(cause);
    } else if (overfill_edge) {
      enter_fault(Fault::kOverfill);
    } else {
      run_cycle(in.plant, present_edge);
    }
  } else if (start_edge && !stop_requested) {
    ++counters_.starts;
    fault_ = Fault::kNone;
    state_ = resume_;
    run_cycle(in.plant, present_edge);
  }
  if (!running() && present_edge && resume_ == State::kMoving) {
    // The belt's last step brought a bottle to the sensor, seen only now
    // (in the stop cycle, or first after a link outage). That edge will not
    // come again: keep it, so START resumes with the whole approach to go.
    resume_ = State::kApproach;
    approach_left_ = config_.approach_steps;
  }
  outputs_.lamp_neighbour_unknown =
      in.prev_run == NeighbourState::kUnknown || in.next_run == NeighbourState::kUnknown;
  update_outputs();
  return outputs_;
}

const ControllerOutputs& Controller::force_safe() {
  if (running()) stop(StopCause::kLinkLost);
  start_.forget();
  update_outputs();
  return outputs_;
}

void Controller::run_cycle(const Sensors& s, bool present_edge) {
  switch (state_) {
    case State::kMoving:
      if (!present_edge) return;
      approach_left_ = config_.approach_steps;
      state_ = State::kApproach;
      // fall through - with approach_steps == 0 the bottle is already in place
    case State::kApproach:
      if (approach_left_ > 0u) {
        --approach_left_;
        return;
      }
      state_ = State::kFilling;
      fill_steps_ = 0;
      // fall through - open the valve in the cycle the bottle arrives
    case State::kFilling:
      if (s.level_full) {
        ++counters_.bottles_filled;
        state_ = State::kMoving;
      } else if (config_.sensor_at_valve && !s.bottle_present) {
        enter_fault(Fault::kBottleLost);
      } else if (fill_steps_ >= config_.fill_timeout_steps) {
        enter_fault(Fault::kFillTimeout);
      } else {
        ++fill_steps_;
      }
      return;
    case State::kStopped:
    case State::kFault:
      return;
  }
}

void Controller::stop(StopCause cause) {
  ++counters_.stops[static_cast<uint8_t>(cause)];
  resume_ = state_;  // the belt stands still: resuming later is exact
  state_ = State::kStopped;
}

void Controller::enter_fault(Fault fault) {
  ++counters_.stops[static_cast<uint8_t>(StopCause::kFault)];
  fault_ = fault;
  resume_ = State::kMoving;
  state_ = State::kFault;
}

void Controller::update_outputs() {
  outputs_.run = running() ? RunState::kRunning : RunState::kStopped;
  outputs_.plant.motor_on = state_ == State::kMoving || state_ == State::kApproach;
  outputs_.plant.valve_open = state_ == State::kFilling;
  outputs_.lamp_fault = state_ == State::kFault;
}

}  // namespace plant
}  // namespace mb2co
