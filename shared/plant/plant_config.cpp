#include "plant/plant_config.h"

#include <string.h>

#include "plant/text_buffer.h"

namespace mb2co {
namespace plant {
namespace {

// Ranges keep every derived quantity inside uint32_t: positions in µm up to
// 1e8, levels in µL up to 1e7, flow per step up to 1e7 µL.
const ConfigKey kKeys[] = {
    {"step_ms", &PlantConfig::step_ms, 1, 1000},
    {"conveyor_speed_mm_s", &PlantConfig::conveyor_speed_mm_s, 1, 5000},
    {"conveyor_length_mm", &PlantConfig::conveyor_length_mm, 100, 100000},
    {"bottle_spacing_mm", &PlantConfig::bottle_spacing_mm, 10, 100000},
    {"valve_position_mm", &PlantConfig::valve_position_mm, 1, 100000},
    {"sensor_to_valve_mm", &PlantConfig::sensor_to_valve_mm, 0, 100000},
    {"sensor_window_mm", &PlantConfig::sensor_window_mm, 1, 1000},
    {"fill_level_ml", &PlantConfig::fill_level_ml, 1, 10000},
    {"overfill_ml", &PlantConfig::overfill_ml, 1, 10000},
    {"bottle_capacity_ml", &PlantConfig::bottle_capacity_ml, 1, 10000},
    {"fill_flow_ml_s", &PlantConfig::fill_flow_ml_s, 1, 10000},
    {"fill_timeout_ms", &PlantConfig::fill_timeout_ms, 1, 3600000},
};
const size_t kKeyCount = sizeof kKeys / sizeof kKeys[0];
static_assert(kKeyCount == kConfigKeyCount, "kConfigKeyCount matches the table");

uint32_t div_round_up(uint32_t a, uint32_t b) {
  return a / b + (a % b != 0u ? 1u : 0u);
}

uint16_t key_bit(uint32_t PlantConfig::*field) {
  for (size_t i = 0; i < kKeyCount; ++i) {
    if (kKeys[i].field == field) return static_cast<uint16_t>(1u << i);
  }
  return 0;
}

// The mask of keys a rule reads (avr-g++ has no <initializer_list>).
uint16_t keys() {
  return 0;
}
template <typename... Rest>
uint16_t keys(uint32_t PlantConfig::*first, Rest... rest) {
  return static_cast<uint16_t>(key_bit(first) | keys(rest...));
}

// Marks the keys a failed rule reads and starts its message.
TextBuffer blame(ConfigError& error, uint16_t& involved, uint16_t rule_keys) {
  involved = rule_keys;
  return TextBuffer(error.message, sizeof error.message);
}

}  // namespace

const ConfigKey& config_key(size_t index) {
  return kKeys[index];
}

size_t find_config_key(const char* name, size_t length) {
  for (size_t i = 0; i < kKeyCount; ++i) {
    if (strlen(kKeys[i].name) == length && memcmp(kKeys[i].name, name, length) == 0) return i;
  }
  return kKeyCount;
}

uint32_t travel_um_per_step(const PlantConfig& c) {
  return c.conveyor_speed_mm_s * c.step_ms;
}

uint32_t flow_ul_per_step(const PlantConfig& c) {
  return c.fill_flow_ml_s * c.step_ms;
}

uint32_t approach_steps(const PlantConfig& c) {
  // The rising edge comes when the bottle centre is within one step past the
  // window's upstream edge; centring it under the valve needs d + w/2 more.
  return (c.sensor_to_valve_mm * 1000u + c.sensor_window_mm * 500u) / travel_um_per_step(c);
}

uint32_t nominal_fill_steps(const PlantConfig& c) {
  return div_round_up(c.fill_level_ml * 1000u, flow_ul_per_step(c));
}

uint32_t fill_timeout_steps(const PlantConfig& c) {
  return div_round_up(c.fill_timeout_ms, c.step_ms);
}

bool check_plant_config(const PlantConfig& c, ConfigError& error, uint16_t& involved) {
  using P = PlantConfig;
  for (size_t i = 0; i < kKeyCount; ++i) {
    const uint32_t value = c.*kKeys[i].field;
    if (value < kKeys[i].min || value > kKeys[i].max) {
      blame(error, involved, keys(kKeys[i].field))
          .add(kKeys[i].name)
          .add(": value ")
          .add_u32(value)
          .add(" out of range ")
          .add_u32(kKeys[i].min)
          .add("..")
          .add_u32(kKeys[i].max);
      return false;
    }
  }
  const uint32_t travel_um = travel_um_per_step(c);
  if (!(c.fill_level_ml < c.overfill_ml && c.overfill_ml <= c.bottle_capacity_ml)) {
    blame(error, involved, keys(&P::fill_level_ml, &P::overfill_ml, &P::bottle_capacity_ml))
        .add("need fill_level_ml < overfill_ml <= bottle_capacity_ml (have ")
        .add_u32(c.fill_level_ml)
        .add(", ")
        .add_u32(c.overfill_ml)
        .add(", ")
        .add_u32(c.bottle_capacity_ml)
        .add(")");
    return false;
  }
  // The controller closes the valve one step after "full" is seen: the level
  // may rise by one step of flow past fill_level_ml, never past overfill_ml.
  if (c.fill_level_ml * 1000u + flow_ul_per_step(c) > c.overfill_ml * 1000u) {
    blame(error, involved, keys(&P::fill_flow_ml_s, &P::step_ms, &P::fill_level_ml, &P::overfill_ml))
        .add("one step of flow (fill_flow_ml_s x step_ms = ")
        .add_u32(flow_ul_per_step(c))
        .add(" uL) is more than overfill_ml - fill_level_ml: bottles could overfill");
    return false;
  }
  // The bottle stops within ± one step of the valve's centre: that must stay
  // inside the window the valve reaches.
  if (travel_um * 2u > c.sensor_window_mm * 1000u) {
    blame(error, involved, keys(&P::conveyor_speed_mm_s, &P::step_ms, &P::sensor_window_mm))
        .add("the conveyor moves ")
        .add_u32(travel_um)
        .add(" um per step (conveyor_speed_mm_s x step_ms), more than half of sensor_window_mm");
    return false;
  }
  // One bottle at a time between the sensor and the valve.
  if (c.bottle_spacing_mm <= c.sensor_to_valve_mm + c.sensor_window_mm) {
    blame(error, involved, keys(&P::bottle_spacing_mm, &P::sensor_to_valve_mm, &P::sensor_window_mm))
        .add("bottle_spacing_mm must exceed sensor_to_valve_mm + sensor_window_mm (")
        .add_u32(c.sensor_to_valve_mm + c.sensor_window_mm)
        .add(")");
    return false;
  }
  // New bottles appear at 0 and must reach the sensor from outside its window.
  if (c.valve_position_mm <= c.sensor_to_valve_mm + c.sensor_window_mm) {
    blame(error, involved, keys(&P::valve_position_mm, &P::sensor_to_valve_mm, &P::sensor_window_mm))
        .add("valve_position_mm must exceed sensor_to_valve_mm + sensor_window_mm (")
        .add_u32(c.sensor_to_valve_mm + c.sensor_window_mm)
        .add(")");
    return false;
  }
  if (c.valve_position_mm + c.sensor_window_mm >= c.conveyor_length_mm) {
    blame(error, involved, keys(&P::valve_position_mm, &P::sensor_window_mm, &P::conveyor_length_mm))
        .add("valve_position_mm + sensor_window_mm must be less than conveyor_length_mm");
    return false;
  }
  if (c.conveyor_length_mm / c.bottle_spacing_mm + 1u > kMaxBottles) {
    blame(error, involved, keys(&P::conveyor_length_mm, &P::bottle_spacing_mm))
        .add("more than ")
        .add_u32(kMaxBottles)
        .add(" bottles would fit on the conveyor (conveyor_length_mm / bottle_spacing_mm + 1)");
    return false;
  }
  if (fill_timeout_steps(c) <= nominal_fill_steps(c)) {
    blame(error, involved, keys(&P::fill_timeout_ms, &P::fill_level_ml, &P::fill_flow_ml_s, &P::step_ms))
        .add("fill_timeout_ms must be longer than the nominal fill time (")
        .add_u32(nominal_fill_steps(c) * c.step_ms)
        .add(" ms)");
    return false;
  }
  return true;
}

}  // namespace plant
}  // namespace mb2co
