#include "plant/plant.h"

namespace mb2co {
namespace plant {
namespace {

uint8_t ring_index(uint8_t head, uint8_t offset) {
  return static_cast<uint8_t>((head + offset) % kMaxBottles);
}

}  // namespace

Plant::Plant(const PlantConfig& config)
    : config_(config),
      travel_um_(travel_um_per_step(config)),
      flow_ul_(flow_ul_per_step(config)),
      valve_um_(config.valve_position_mm * 1000u),
      sensor_um_((config.valve_position_mm - config.sensor_to_valve_mm) * 1000u),
      half_window_um_(config.sensor_window_mm * 500u),
      bottles_(),
      head_(0),
      count_(0),
      steps_(0) {
  reset();
}

void Plant::reset() {
  head_ = 0;
  count_ = 0;
  steps_ = 0;
  counters_ = PlantCounters();
  add_bottle(0);
}

const Bottle& Plant::bottle(uint8_t index) const {
  return bottles_[ring_index(head_, index)];
}

int8_t Plant::bottle_near(uint32_t point_um) const {
  for (uint8_t i = 0; i < count_; ++i) {
    const uint32_t pos = bottle(i).position_um;
    const uint32_t distance = pos > point_um ? pos - point_um : point_um - pos;
    if (distance <= half_window_um_) return static_cast<int8_t>(i);
  }
  return -1;
}

// Precondition count_ < kMaxBottles (check_plant_config() guarantees room:
// length / spacing + 1 <= kMaxBottles).
void Plant::add_bottle(uint32_t position_um) {
  bottles_[ring_index(head_, count_)] = Bottle{position_um, 0u, false};
  ++count_;
  ++counters_.bottles_in;
}

void Plant::pour() {
  const int8_t at_valve = bottle_near(valve_um_);
  if (at_valve < 0) {
    counters_.spilled_ul += flow_ul_;
    return;
  }
  Bottle& b = bottles_[ring_index(head_, static_cast<uint8_t>(at_valve))];
  const uint32_t capacity_ul = config_.bottle_capacity_ml * 1000u;
  b.level_ul += flow_ul_;  // <= 2e7: no overflow
  if (b.level_ul > capacity_ul) {
    counters_.spilled_ul += b.level_ul - capacity_ul;
    b.level_ul = capacity_ul;
  }
  if (!b.overfilled && b.level_ul > config_.overfill_ml * 1000u) {
    b.overfilled = true;
    ++counters_.overfilled;
  }
}

void Plant::hand_off_front() {
  const Bottle& b = bottle(0);
  ++counters_.handed_off;
  if (b.level_ul > config_.overfill_ml * 1000u) {
    ++counters_.handed_off_overfilled;
  } else if (b.level_ul >= config_.fill_level_ml * 1000u) {
    ++counters_.handed_off_filled;
  } else {
    ++counters_.handed_off_underfilled;
  }
  head_ = ring_index(head_, 1);
  --count_;
}

void Plant::step(const Actuators& actuators) {
  ++steps_;
  if (actuators.valve_open) pour();
  if (!actuators.motor_on) return;
  for (uint8_t i = 0; i < count_; ++i) bottles_[ring_index(head_, i)].position_um += travel_um_;
  const uint32_t end_um = config_.conveyor_length_mm * 1000u;
  while (count_ > 0 && bottle(0).position_um >= end_um) hand_off_front();
  // Exact spacing: a new bottle sits `spacing` behind the newest one (at 0
  // when the belt ran empty, possible only when spacing > length).
  const uint32_t spacing_um = config_.bottle_spacing_mm * 1000u;
  while (count_ < kMaxBottles) {
    if (count_ == 0) {
      add_bottle(0);
      continue;
    }
    const uint32_t newest_um = bottle(static_cast<uint8_t>(count_ - 1u)).position_um;
    if (newest_um < spacing_um) break;
    add_bottle(newest_um - spacing_um);
  }
}

Sensors Plant::sensors() const {
  Sensors s;
  s.bottle_present = bottle_near(sensor_um_) >= 0;
  const int8_t at_valve = bottle_near(valve_um_);
  if (at_valve >= 0) {
    const uint32_t level_ul = bottle(static_cast<uint8_t>(at_valve)).level_ul;
    s.level_full = level_ul >= config_.fill_level_ml * 1000u;
    s.overfill = level_ul > config_.overfill_ml * 1000u;
    s.level_ml = static_cast<uint16_t>(level_ul / 1000u);
  }
  return s;
}

}  // namespace plant
}  // namespace mb2co
