// Parameters of one bottling station (conveyor, bottle sensor, fill valve,
// bottles), their ranges, and the cross-checks that make the station safe to
// control. Defaults and units: docs/plant.md.
#pragma once
#include <stddef.h>
#include <stdint.h>

namespace mb2co {
namespace plant {

/// Most bottles on one conveyor at once (the plant's storage is fixed).
constexpr uint8_t kMaxBottles = 16;

/// Whole numbers in the unit at the end of each name. The defaults are the
/// station of docs/plant.md. Plant and controller_config_for() require a
/// config that check_plant_config() accepted.
struct PlantConfig {
  uint32_t step_ms = 10;               ///< fixed integration step = one control cycle
  uint32_t conveyor_speed_mm_s = 100;  ///< belt speed while the motor is on
  uint32_t conveyor_length_mm = 1000;  ///< bottles enter at 0, are handed on at this point
  uint32_t bottle_spacing_mm = 200;    ///< distance between consecutive bottles (infeed)
  uint32_t valve_position_mm = 500;    ///< filling point, from the conveyor start
  uint32_t sensor_to_valve_mm = 0;     ///< bottle sensor this far upstream of the valve
  uint32_t sensor_window_mm = 20;      ///< sensor sees / valve hits a bottle within ±window/2
  uint32_t fill_level_ml = 500;        ///< "full" level switch set point
  uint32_t overfill_ml = 510;          ///< above this a bottle is overfilled (rejected)
  uint32_t bottle_capacity_ml = 550;   ///< above this liquid spills
  uint32_t fill_flow_ml_s = 100;       ///< flow through the open valve
  uint32_t fill_timeout_ms = 10000;    ///< controller fault if "full" takes longer
};

/// One config key: its name in the file, the field it sets, its range.
struct ConfigKey {
  const char* name;
  uint32_t PlantConfig::*field;
  uint32_t min;
  uint32_t max;
};

/// The table of keys (constant; order = order in docs/plant.md).
constexpr size_t kConfigKeyCount = 12;      ///< fits the uint16_t key masks below
const ConfigKey& config_key(size_t index);  ///< index < kConfigKeyCount
/// Index of the key called `name` (`length` bytes, not NUL-terminated), or
/// kConfigKeyCount when there is none.
size_t find_config_key(const char* name, size_t length);

/// What went wrong, for a one-line "file:line:column: message" report.
/// line == 0 means no single line is to blame (e.g. the defaults themselves).
struct ConfigError {
  uint32_t line;
  uint32_t column;
  char message[128];
};

/// Checks every range and the cross-field rules of docs/plant.md ("why the
/// limits"). On failure fills error.message, sets bit k of `involved_keys`
/// for each config_key(k) the failed rule reads, and returns false. Lines are
/// the caller's business (error.line/column are left alone).
bool check_plant_config(const PlantConfig& config, ConfigError& error, uint16_t& involved_keys);

/// Derived quantities (valid config only).
uint32_t travel_um_per_step(const PlantConfig& config);
uint32_t flow_ul_per_step(const PlantConfig& config);
/// Steps the conveyor keeps running after the sensor's rising edge so that the
/// bottle stops centred under the valve (within ± one step of travel).
uint32_t approach_steps(const PlantConfig& config);
/// Steps to fill an empty bottle to fill_level_ml (rounded up).
uint32_t nominal_fill_steps(const PlantConfig& config);
/// fill_timeout_ms in steps (rounded up).
uint32_t fill_timeout_steps(const PlantConfig& config);

}  // namespace plant
}  // namespace mb2co
