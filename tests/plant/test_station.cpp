// Plant and controller in closed loop, as the app and the line simulator run
// them: exact timing, safe stops, STOP2 along a chain, and no overfill or
// spill in normal running for any configuration the checks accept.
#include <gtest/gtest.h>

#include <vector>

#include "plant/plant_config.h"
#include "station.h"

namespace mb2co {
namespace plant {
namespace {

TEST(Station, FirstBottleStopsCentredAndIsFilledToTheMillilitre) {
  Station s;
  s.press_start();
  uint32_t motor_cycles = 2;  // the START cycle and the release cycle moved it
  while (!s.cycle().plant.valve_open) {
    ++motor_cycles;
    ASSERT_LT(motor_cycles, 10000u);
  }
  // 490 mm to the sensor's edge, 10 mm of approach: centred at the valve.
  EXPECT_EQ(motor_cycles, 500u);
  EXPECT_EQ(s.plant.bottle(0).position_um, 500000u);
  uint32_t valve_cycles = 1;
  while (s.cycle().plant.valve_open) ++valve_cycles;
  EXPECT_EQ(valve_cycles, 500u);  // 500 mL at 1 mL per step
  EXPECT_EQ(s.plant.bottle(0).level_ul, 500000u);
  EXPECT_EQ(s.controller.counters().bottles_filled, 1u);
  EXPECT_EQ(s.plant.counters().spilled_ul, 0u);
}

TEST(Station, LongRunFillsEveryBottleItHandsOn) {
  Station s;
  s.press_start();
  s.run(100000);
  const PlantCounters& p = s.plant.counters();
  // 700 cycles per bottle: 200 mm of belt + 500 mL of filling.
  EXPECT_GE(p.handed_off, 100000u / 700u - 3u);
  EXPECT_EQ(p.handed_off_filled, p.handed_off);
  EXPECT_EQ(p.overfilled, 0u);
  EXPECT_EQ(p.spilled_ul, 0u);
  EXPECT_GE(s.controller.counters().bottles_filled, p.handed_off);
  EXPECT_EQ(s.controller.counters().overfills, 0u);
  EXPECT_EQ(s.controller.fault(), Fault::kNone);
  EXPECT_TRUE(s.controller.running());
}

// Bottle positions and levels, to prove nothing moved or poured.
std::vector<Bottle> snapshot(const Plant& p) {
  std::vector<Bottle> b;
  for (uint8_t i = 0; i < p.bottle_count(); ++i) b.push_back(p.bottle(i));
  return b;
}

bool same(const std::vector<Bottle>& a, const std::vector<Bottle>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].position_um != b[i].position_um || a[i].level_ul != b[i].level_ul) return false;
  }
  return true;
}

TEST(Station, StopFreezesThePlantFromTheNextStepOn) {
  const struct {
    uint32_t cycles;
    State state;
  } cases[] = {
      {100, State::kMoving}, {495, State::kApproach}, {700, State::kFilling}, {990, State::kFilling}};
  for (const auto& c : cases) {
    Station s;
    s.press_start();
    s.run(c.cycles);
    ASSERT_EQ(s.controller.state(), c.state) << c.cycles;
    s.panel.stop_pressed = true;
    const std::vector<Bottle> before = snapshot(s.plant);
    s.cycle();  // the stop is seen here, and this cycle's step is already safe
    EXPECT_TRUE(same(before, snapshot(s.plant))) << c.cycles;
    s.panel.stop_pressed = false;
    s.run(1000);
    EXPECT_TRUE(same(before, snapshot(s.plant))) << c.cycles;
    s.press_start();
    EXPECT_EQ(s.controller.state(), c.state) << c.cycles;
  }
}

TEST(Station, Stop2StopsThisStationAndTheNextOneNotThePrevious) {
  // Three stations; the gateway passes station k's STOP2 counter to k+1.
  Station line[3];
  for (Station& s : line) s.press_start();
  for (int i = 0; i < 300; ++i) {
    for (Station& s : line) s.cycle();
  }
  line[1].panel.stop2_pressed = true;
  ++line[1].panel.local_stop2_events;
  for (int k = 0; k < 3; ++k) {
    if (k > 0) line[k].panel.prev_stop2_events = line[k - 1].panel.local_stop2_events;
    line[k].cycle();
  }
  EXPECT_TRUE(line[0].controller.running());
  EXPECT_FALSE(line[1].controller.running());
  EXPECT_FALSE(line[2].controller.running());
  EXPECT_EQ(line[1].controller.counters().stops[static_cast<uint8_t>(StopCause::kLocalStop2)], 1u);
  EXPECT_EQ(line[2].controller.counters().stops[static_cast<uint8_t>(StopCause::kPrevStop2)], 1u);
  EXPECT_EQ(line[2].controller.outputs().run, RunState::kStopped);
}

// A small deterministic generator (no <random>: the sequence must be the same
// on every standard library).
struct Lcg {
  uint32_t state;
  uint32_t next() {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  }
  uint32_t in(uint32_t lo, uint32_t hi) { return lo + next() % (hi - lo + 1u); }
};

PlantConfig random_config(Lcg& r) {
  PlantConfig c;
  c.step_ms = r.in(1, 50);
  c.conveyor_speed_mm_s = r.in(10, 1000);
  c.conveyor_length_mm = r.in(300, 3000);
  c.bottle_spacing_mm = r.in(60, 800);
  c.valve_position_mm = r.in(100, c.conveyor_length_mm - 50u);
  c.sensor_to_valve_mm = r.in(0, 3) == 0u ? 0u : r.in(1, 200);
  c.sensor_window_mm = r.in(5, 100);
  c.fill_level_ml = r.in(50, 1000);
  c.overfill_ml = c.fill_level_ml + r.in(1, 50);
  c.bottle_capacity_ml = c.overfill_ml + r.in(0, 100);
  c.fill_flow_ml_s = r.in(10, 2000);
  c.fill_timeout_ms = nominal_fill_steps(c) * c.step_ms * 2u + c.step_ms;
  return c;
}

TEST(Station, NoOverfillNorSpillInNormalRunningForAnyAcceptedConfig) {
  Lcg r{2024};
  int accepted = 0;
  for (int attempt = 0; attempt < 20000 && accepted < 150; ++attempt) {
    const PlantConfig c = random_config(r);
    ConfigError error{};
    uint16_t involved = 0;
    if (!check_plant_config(c, error, involved)) continue;
    ++accepted;

    // The operator and the neighbours do anything but break the plant.
    Station s(c);
    s.press_start();
    for (uint32_t i = 0; i < 40000; ++i) {
      const uint32_t dice = r.in(0, 999);
      s.panel.stop_pressed = dice == 0u;
      s.panel.stop2_pressed = dice == 1u;
      if (dice == 1u) ++s.panel.local_stop2_events;
      if (dice == 2u) ++s.panel.prev_stop2_events;
      s.panel.start_pressed = dice >= 990u;
      if (dice == 3u) {
        s.outage(r.in(1, 50));
      } else {
        s.cycle();
      }
    }
    const PlantCounters& p = s.plant.counters();
    const ControllerCounters& k = s.controller.counters();
    SCOPED_TRACE(::testing::Message()
                 << "config #" << accepted << ": step " << c.step_ms << " ms, speed " << c.conveyor_speed_mm_s
                 << ", window " << c.sensor_window_mm << ", sensor->valve " << c.sensor_to_valve_mm
                 << ", fill " << c.fill_level_ml << "/" << c.overfill_ml << " mL, flow " << c.fill_flow_ml_s);
    EXPECT_EQ(p.overfilled, 0u);
    EXPECT_EQ(p.spilled_ul, 0u);
    EXPECT_EQ(p.handed_off_underfilled, 0u);
    EXPECT_EQ(p.handed_off_filled, p.handed_off);
    EXPECT_EQ(k.overfills, 0u);
    EXPECT_EQ(k.stops[static_cast<uint8_t>(StopCause::kFault)], 0u);
    EXPECT_GT(k.starts, 1u);
    EXPECT_GT(k.stops[static_cast<uint8_t>(StopCause::kStopButton)] +
                  k.stops[static_cast<uint8_t>(StopCause::kLinkLost)],
              0u);
    EXPECT_GT(k.bottles_filled, 0u);
  }
  EXPECT_EQ(accepted, 150);
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
