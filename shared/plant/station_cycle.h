// The PC's station cycle (docs/plant.md "The cycle"): the registers one read
// brought, decoded into the operator panel's state and the controller's
// inputs; one controller step and one plant step; the RUN command to write
// back. mb2co-plant (pcapp/plant/station_cycle.h adds its texts and log
// columns) and the simulator's PCs (hil/sim/pc_programs.h) run this one
// cycle; how the registers travel is theirs.
#pragma once
#include <stdint.h>

#include "plant/controller.h"
#include "plant/plant.h"
#include "plant/station_fields.h"

namespace mb2co {
namespace plant {

/// What the gateway reported in one read (0 for fields the read lacks).
struct Panel {
  uint8_t buttons = 0;  ///< gateway::Button bits, debounced
  uint8_t run_state = 0;
  uint8_t stop_cause = 0;  ///< gateway::StopCause
  uint8_t leds = 0;        ///< gateway::Led bits
  uint8_t prev_run = 0, prev_status = 0, next_run = 0, next_status = 0;
  uint8_t error_register = 0, nmt_state = 0;
  uint16_t stop2_count = 0, prev_stop2 = 0, start_count = 0, stop_count = 0;
};

/// Fields the cycle cannot work without, and those it shows when mapped.
constexpr int kStationReadCount = 9;
extern const Field kStationReads[kStationReadCount];
constexpr int kStationOptionalReadCount = 5;
extern const Field kStationOptionalReads[kStationOptionalReadCount];

/// One read decoded: `read(field)` is the field's value, 0 when the read
/// lacks it.
template <class Read>
Panel decode_panel(const Read& read) {
  auto u8 = [&](Field f) { return static_cast<uint8_t>(read(f)); };
  auto u16 = [&](Field f) { return static_cast<uint16_t>(read(f)); };
  Panel p;
  p.buttons = u8(Field::kInputs);
  p.run_state = u8(Field::kRunState);
  p.stop_cause = u8(Field::kStopCause);
  p.leds = u8(Field::kLeds);
  p.prev_run = u8(Field::kPrevRun);
  p.prev_status = u8(Field::kPrevStatus);
  p.next_run = u8(Field::kNextRun);
  p.next_status = u8(Field::kNextStatus);
  p.error_register = u8(Field::kErrorRegister);
  p.nmt_state = u8(Field::kNmtState);
  p.stop2_count = u16(Field::kStop2Count);
  p.prev_stop2 = u16(Field::kPrevStop2);
  p.start_count = u16(Field::kStartCount);
  p.stop_count = u16(Field::kStopCount);
  return p;
}

/// A neighbour as the controller sees it: status 1 (alive) gives its RUN
/// state, 0 unknown (heartbeat lost), 2 none (end of the chain) absent; with
/// the flag kNeighbourNotHeard (no TPDO1 yet) unknown.
NeighbourState neighbour_state(uint8_t status, uint8_t run);

/// The controller's inputs; the previous STOP2 counter counts only when
/// heard (prev_status without kNeighbourNotHeard). `run_confirmed`: the RUN command 1 was written
/// before the previous read already, so a firmware RUN state 0 with stop
/// cause "STOP button" is a latched STOP press; it counts as STOP held, and
/// a click shorter than one cycle (never seen as a level) still stops.
ControllerInputs controller_inputs(const Panel& panel, bool run_confirmed, const Sensors& sensors);

class StationCycle {
 public:
  /// `config` must have passed check_plant_config().
  explicit StationCycle(const PlantConfig& config);

  /// One cycle on a fresh read: the controller steps on `panel`, the plant
  /// one step_ms. Returns the RUN command to write (true: running).
  bool step(const Panel& panel);
  /// One cycle without a read (the plant keeps its time with the last, or
  /// after link_lost() the safe, actuators).
  void step_offline();
  /// The link is gone: the controller makes everything safe now, and what
  /// was read and written before no longer counts (the gateway may come
  /// back reset).
  void link_lost();

  const Panel& panel() const { return panel_; }
  /// A read since the start / the last link loss.
  bool panel_known() const { return panel_known_; }
  /// The RUN command the last step wrote.
  bool run_command() const { return run_written_[0]; }
  const Controller& controller() const { return controller_; }
  const Plant& plant() const { return plant_; }

 private:
  Plant plant_;
  Controller controller_;
  Panel panel_;
  bool panel_known_ = false;
  /// RUN commands written at the last two writes (the newest first): a
  /// command is confirmed once it preceded a whole read (controller_inputs).
  bool run_written_[2] = {false, false};
};

}  // namespace plant
}  // namespace mb2co
