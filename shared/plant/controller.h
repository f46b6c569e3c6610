// The station controller: START/STOP/STOP2 operator logic (seed 000 §10) and
// the filling cycle of one bottling station. Plain structs in, plain structs
// out; the app and the line simulator do the Modbus / CANopen side.
//
// One cycle, exactly once per plant step (the plant's step_ms):
//   outputs = controller.step(inputs incl. plant.sensors());  plant.step(outputs.plant);
// and the app writes outputs.run to the Arduino every cycle.
#pragma once
#include <stdint.h>

#include "gateway/stop_cause.h"
#include "plant/edges.h"
#include "plant/plant.h"
#include "plant/plant_config.h"

namespace mb2co {
namespace plant {

/// Own RUN state as written to the Arduino.
enum class RunState : uint8_t { kStopped = 0, kRunning = 1 };

/// A neighbour's RUN state as the gateway reports it. `unknown` = its
/// heartbeat is lost (never taken for running); `absent` = end of the chain.
enum class NeighbourState : uint8_t { kAbsent = 0, kUnknown = 1, kStopped = 2, kRunning = 3 };

/// The controller's stop counters (ControllerCounters::stops), one per cause
/// it tells apart. Not a second list of causes: each is one of the line's
/// causes (gateway::StopCause, the values of 2100h/4), reported_cause()
/// says which; only the numbering differs (a dense counter index, and the
/// order of the PC app's reports).
enum class StopCause : uint8_t {
  kStopButton = 0,  ///< STOP pressed
  kLocalStop2 = 1,  ///< STOP2 pressed on this station's panel
  kPrevStop2 = 2,   ///< STOP2 pressed on the previous station
  kLinkLost = 3,    ///< force_safe(): the serial link to the Arduino is gone
  kFault = 4,       ///< the controller found the plant misbehaving
};
constexpr uint8_t kStopCauseCount = 5;

/// The cause the firmware reports in 2100h/4 for the same stop: the PC's lost
/// link is the silence the firmware's watchdog sees from its side; a fault is
/// the controller's own decision, which the firmware sees as RUN command 0.
constexpr gateway::StopCause reported_cause(StopCause cause) {
  return cause == StopCause::kStopButton   ? gateway::kCauseStopButton
         : cause == StopCause::kLocalStop2 ? gateway::kCauseStop2Here
         : cause == StopCause::kPrevStop2  ? gateway::kCauseStop2Previous
         : cause == StopCause::kLinkLost   ? gateway::kCausePcSilent
                                           : gateway::kCauseNone;
}

enum class Fault : uint8_t {
  kNone = 0,
  kFillTimeout = 1,  ///< "full" not reached within fill_timeout_steps
  kBottleLost = 2,   ///< sensor at the valve lost the bottle while filling
  kOverfill = 3,     ///< the overfill switch rose while running
};

/// stopped and fault are safe (motor off, valve closed). moving, approach and
/// filling are RUNNING: the filling cycle moving -> approach -> filling -> moving.
enum class State : uint8_t { kStopped = 0, kFault = 1, kMoving = 2, kApproach = 3, kFilling = 4 };

/// Everything the controller reads in one cycle.
struct ControllerInputs {
  bool start_pressed = false;  ///< button levels, true = pressed
  bool stop_pressed = false;
  bool stop2_pressed = false;
  uint16_t local_stop2_events = 0;  ///< this panel's STOP2 event counter (wraps)
  uint16_t prev_stop2_events = 0;   ///< previous station's STOP2 event counter (wraps)
  /// False while the gateway has not heard the previous station's counter
  /// since its reset (gateway::kNeighbourNotHeard): prev_stop2_events is a
  /// placeholder then. Nothing is counted from it; the next known value is
  /// compared with the last known one, so events meanwhile count once.
  bool prev_stop2_known = true;
  NeighbourState prev_run = NeighbourState::kAbsent;
  NeighbourState next_run = NeighbourState::kAbsent;
  Sensors plant;
};

/// Everything the controller decides in one cycle.
struct ControllerOutputs {
  RunState run = RunState::kStopped;    ///< write to the Arduino every cycle
  Actuators plant;                      ///< apply to the plant's next step
  bool lamp_fault = false;              ///< a fault waits for START
  bool lamp_neighbour_unknown = false;  ///< a neighbour's state is unknown (heartbeat lost)
};

/// Counters only grow (wrap after 2^32).
struct ControllerCounters {
  uint32_t starts = 0;
  uint32_t bottles_filled = 0;           ///< filling cycles that ended at "full"
  uint32_t overfills = 0;                ///< rising edges of the overfill switch
  uint32_t stops[kStopCauseCount] = {};  ///< RUNNING -> stopped/fault, by StopCause
  uint32_t local_stop2_events = 0;       ///< STOP2 events seen on the counters
  uint32_t prev_stop2_events = 0;
};

/// What the controller must know about the plant it drives.
struct ControllerConfig {
  uint32_t approach_steps = 0;      ///< belt steps from the sensor's edge to the valve
  uint32_t fill_timeout_steps = 1;  ///< longest filling before Fault::kFillTimeout
  bool sensor_at_valve = true;      ///< sensor_to_valve_mm == 0: the bottle must stay seen while filling
};

/// The ControllerConfig for a plant (config must pass check_plant_config()).
ControllerConfig controller_config_for(const PlantConfig& config);

/// Starts stopped, no fault. Caller owns it; no heap; not thread-safe.
class Controller {
 public:
  explicit Controller(const ControllerConfig& config);

  /// One control cycle. Any stop input seen (STOP or STOP2 held, a new local
  /// or previous-station STOP2 event) stops a running station in this very
  /// cycle: the returned outputs are already safe. Stop inputs beat START.
  /// A stopped station runs on a rising edge of START with no stop input,
  /// resuming the filling cycle where it was stopped; after a fault it
  /// resumes at `moving` (the faulty bottle is passed on, not refilled).
  /// A bottle reaching the sensor while the station is not running (the
  /// belt's last step before the stop) is remembered, never skipped.
  const ControllerOutputs& step(const ControllerInputs& inputs);

  /// The serial link is lost: safe outputs now (counted as link_lost if it
  /// was running); START needs a fresh press once step() is called again.
  /// Counter baselines are kept, so STOP2 events during the outage are seen.
  const ControllerOutputs& force_safe();

  State state() const { return state_; }
  Fault fault() const { return fault_; }
  bool running() const {
    return state_ == State::kMoving || state_ == State::kApproach || state_ == State::kFilling;
  }
  const ControllerOutputs& outputs() const { return outputs_; }
  const ControllerCounters& counters() const { return counters_; }

 private:
  /// The filling cycle; `state_` is a running state.
  void run_cycle(const Sensors& sensors, bool present_edge);
  void stop(StopCause cause);
  void enter_fault(Fault fault);
  void update_outputs();

  ControllerConfig config_;
  State state_ = State::kStopped;
  State resume_ = State::kMoving;  ///< running state START resumes
  Fault fault_ = Fault::kNone;
  uint32_t approach_left_ = 0;
  uint32_t fill_steps_ = 0;  ///< steps with the valve open for the current bottle
  RisingEdge start_;
  RisingEdge present_;
  RisingEdge overfill_;
  EventCounter local_stop2_;
  EventCounter prev_stop2_;
  ControllerOutputs outputs_;
  ControllerCounters counters_;
};

}  // namespace plant
}  // namespace mb2co
