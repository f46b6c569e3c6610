// One bottling station, integrated in fixed steps with integer arithmetic:
// a conveyor carries bottles past a bottle sensor to a fill valve and hands
// them on to the next station. Deterministic: the same config and the same
// actuator sequence give bit-identical states on every machine.
#pragma once
#include <stdint.h>

#include "plant/plant_config.h"

namespace mb2co {
namespace plant {

/// What the controller drives, applied for one whole step.
struct Actuators {
  bool motor_on = false;
  bool valve_open = false;
};

/// What the controller sees. "At the valve" = the bottle whose centre is
/// within ±sensor_window_mm/2 of valve_position_mm (at most one, by config).
struct Sensors {
  bool bottle_present = false;  ///< a bottle centre within ±window/2 of the sensor
  bool level_full = false;      ///< bottle at the valve holds >= fill_level_ml
  bool overfill = false;        ///< bottle at the valve holds > overfill_ml
  uint16_t level_ml = 0;        ///< level of the bottle at the valve, 0 without one
};

/// A bottle on the belt. Position of its centre from the conveyor start.
struct Bottle {
  uint32_t position_um;
  uint32_t level_ul;
  bool overfilled;  ///< went above overfill_ml at some point
};

/// Ground truth, for the simulator's checks and the app's display. These only
/// grow (wrap after 2^32 bottles).
struct PlantCounters {
  uint32_t bottles_in = 0;         ///< placed on the belt by the infeed
  uint32_t handed_off = 0;         ///< passed to the next station
  uint32_t handed_off_filled = 0;  ///<   of those: fill_level_ml..overfill_ml
  uint32_t handed_off_underfilled = 0;
  uint32_t handed_off_overfilled = 0;
  uint32_t overfilled = 0;  ///< bottles that went above overfill_ml
  uint64_t spilled_ul = 0;  ///< liquid that missed a bottle or ran over
};

/// Caller owns it; no heap; bounded (kMaxBottles). Not thread-safe.
class Plant {
 public:
  /// `config` must have passed check_plant_config(); it is copied.
  explicit Plant(const PlantConfig& config);

  /// Empty belt with one empty bottle at position 0, counters zero.
  void reset();

  /// Advances exactly config.step_ms: first the open valve pours one step of
  /// flow into the bottle at the valve (or onto the belt), then a running belt
  /// moves travel_um_per_step(), bottles at or past the end are handed off,
  /// and the infeed places new bottles bottle_spacing_mm behind the newest.
  void step(const Actuators& actuators);

  /// Sensor readings for the current state (after the last step).
  Sensors sensors() const;

  uint8_t bottle_count() const { return count_; }
  /// index 0 = furthest downstream; index < bottle_count().
  const Bottle& bottle(uint8_t index) const;
  const PlantCounters& counters() const { return counters_; }
  const PlantConfig& config() const { return config_; }
  uint32_t steps() const { return steps_; }

 private:
  /// Index of the bottle whose centre is within ±window/2 of `point_um`, or -1.
  int8_t bottle_near(uint32_t point_um) const;
  void pour();
  void hand_off_front();
  void add_bottle(uint32_t position_um);

  PlantConfig config_;
  uint32_t travel_um_;
  uint32_t flow_ul_;
  uint32_t valve_um_;
  uint32_t sensor_um_;
  uint32_t half_window_um_;
  Bottle bottles_[kMaxBottles];  ///< ring: [head_, head_ + count_) oldest first
  uint8_t head_;
  uint8_t count_;
  uint32_t steps_;
  PlantCounters counters_;
};

}  // namespace plant
}  // namespace mb2co
