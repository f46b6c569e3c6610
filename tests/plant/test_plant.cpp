// The plant alone, driven by hand-made actuator sequences.
#include <gtest/gtest.h>

#include "plant/plant.h"

namespace mb2co {
namespace plant {
namespace {

const Actuators kIdle{false, false};
const Actuators kMove{true, false};
const Actuators kPour{false, true};

void run(Plant& p, const Actuators& a, uint32_t steps) {
  for (uint32_t i = 0; i < steps; ++i) p.step(a);
}

TEST(Plant, StartsWithOneEmptyBottleAtTheInfeed) {
  Plant p{PlantConfig()};
  ASSERT_EQ(p.bottle_count(), 1u);
  EXPECT_EQ(p.bottle(0).position_um, 0u);
  EXPECT_EQ(p.bottle(0).level_ul, 0u);
  EXPECT_EQ(p.counters().bottles_in, 1u);
  EXPECT_EQ(p.steps(), 0u);
  const Sensors s = p.sensors();
  EXPECT_FALSE(s.bottle_present);
  EXPECT_FALSE(s.level_full);
  EXPECT_FALSE(s.overfill);
  EXPECT_EQ(s.level_ml, 0u);
}

TEST(Plant, IdleStepsChangeNothingButTime) {
  Plant p{PlantConfig()};
  run(p, kIdle, 1000);
  EXPECT_EQ(p.steps(), 1000u);
  ASSERT_EQ(p.bottle_count(), 1u);
  EXPECT_EQ(p.bottle(0).position_um, 0u);
}

TEST(Plant, BeltMovesExactlyOneStepOfTravelAndKeepsExactSpacing) {
  Plant p{PlantConfig()};  // 1 mm per step, 200 mm spacing
  run(p, kMove, 199);
  ASSERT_EQ(p.bottle_count(), 1u);
  EXPECT_EQ(p.bottle(0).position_um, 199000u);
  p.step(kMove);
  ASSERT_EQ(p.bottle_count(), 2u);  // the next bottle arrives exactly 200 mm behind
  EXPECT_EQ(p.bottle(0).position_um, 200000u);
  EXPECT_EQ(p.bottle(1).position_um, 0u);
  EXPECT_EQ(p.counters().bottles_in, 2u);
}

TEST(Plant, SpacingStaysExactWhenStepsDoNotDivideIt) {
  PlantConfig c;
  c.conveyor_speed_mm_s = 70;  // 0.7 mm per step; 200 mm is not a multiple
  Plant p{c};
  run(p, kMove, 2000);  // 1400 mm of belt
  for (uint8_t i = 1; i < p.bottle_count(); ++i) {
    EXPECT_EQ(p.bottle(static_cast<uint8_t>(i - 1u)).position_um - p.bottle(i).position_um, 200000u)
        << int(i);
  }
}

TEST(Plant, SensorWindowEdgesAreInclusive) {
  Plant p{PlantConfig()};  // sensor at 500 mm, window ±10 mm
  run(p, kMove, 489);
  EXPECT_FALSE(p.sensors().bottle_present);  // 489 mm
  p.step(kMove);
  EXPECT_TRUE(p.sensors().bottle_present);  // 490 mm
  run(p, kMove, 20);
  EXPECT_TRUE(p.sensors().bottle_present);  // 510 mm
  p.step(kMove);
  EXPECT_FALSE(p.sensors().bottle_present);  // 511 mm
}

TEST(Plant, SensorUpstreamOfTheValve) {
  PlantConfig c;
  c.sensor_to_valve_mm = 100;  // sensor at 400 mm, valve at 500 mm
  Plant p{c};
  run(p, kMove, 400);
  EXPECT_TRUE(p.sensors().bottle_present);
  p.step(kPour);  // sensor sees it, but the valve is 100 mm away: spill
  EXPECT_EQ(p.bottle(0).level_ul, 0u);
  EXPECT_EQ(p.counters().spilled_ul, 1000u);
  run(p, kMove, 100);
  EXPECT_FALSE(p.sensors().bottle_present);
  p.step(kPour);
  EXPECT_EQ(p.bottle(0).level_ul, 1000u);
  EXPECT_EQ(p.sensors().level_ml, 1u);
}

TEST(Plant, OpenValveWithoutBottleSpillsEveryStep) {
  Plant p{PlantConfig()};
  run(p, kPour, 25);
  EXPECT_EQ(p.counters().spilled_ul, 25u * 1000u);
  EXPECT_EQ(p.bottle(0).level_ul, 0u);
}

TEST(Plant, FillingRaisesTheLevelAndTheSwitches) {
  Plant p{PlantConfig()};
  run(p, kMove, 500);  // centred under the valve
  run(p, kPour, 499);
  Sensors s = p.sensors();
  EXPECT_EQ(s.level_ml, 499u);
  EXPECT_FALSE(s.level_full);
  p.step(kPour);
  s = p.sensors();
  EXPECT_EQ(s.level_ml, 500u);
  EXPECT_TRUE(s.level_full);
  EXPECT_FALSE(s.overfill);
  run(p, kPour, 10);
  EXPECT_FALSE(p.sensors().overfill);  // exactly 510 mL is not over 510
  EXPECT_EQ(p.counters().overfilled, 0u);
}

TEST(Plant, StoppedBeltWithOpenValveOverfillsAndSpills) {
  // The hazard the controller exists to prevent.
  Plant p{PlantConfig()};
  run(p, kMove, 500);
  run(p, kPour, 511);
  EXPECT_TRUE(p.sensors().overfill);
  EXPECT_TRUE(p.bottle(0).overfilled);
  EXPECT_EQ(p.counters().overfilled, 1u);
  EXPECT_EQ(p.counters().spilled_ul, 0u);
  run(p, kPour, 100);  // 611 mL poured into a 550 mL bottle
  EXPECT_EQ(p.bottle(0).level_ul, 550000u);
  EXPECT_EQ(p.counters().spilled_ul, 61000u);
  EXPECT_EQ(p.counters().overfilled, 1u);  // one bottle, counted once
}

TEST(Plant, MovingBottlePassingAnOpenValveCatchesSomeLiquid) {
  Plant p{PlantConfig()};
  run(p, kMove, 480);
  run(p, Actuators{true, true}, 40);  // 480..520 mm with the valve open
  // The pour happens before the move, at 490..510 mm: 21 steps inside.
  EXPECT_EQ(p.bottle(0).level_ul, 21000u);
  EXPECT_EQ(p.counters().spilled_ul, 19000u);
}

TEST(Plant, HandOffClassifiesEveryBottle) {
  Plant p{PlantConfig()};
  run(p, kMove, 500);  // bottle 0 at the valve
  run(p, kPour, 505);  // filled (505 mL)
  run(p, kMove, 200);  // bottle 1 at the valve
  run(p, kPour, 520);  // overfilled
  run(p, kMove, 200);  // bottle 2 at the valve: left empty
  EXPECT_EQ(p.counters().handed_off, 0u);
  run(p, kMove, 99);
  EXPECT_EQ(p.counters().handed_off, 0u);  // bottle 0 at 999 mm
  p.step(kMove);
  EXPECT_EQ(p.counters().handed_off, 1u);  // reached 1000 mm: handed on
  EXPECT_EQ(p.counters().handed_off_filled, 1u);
  run(p, kMove, 400);
  EXPECT_EQ(p.counters().handed_off, 3u);
  EXPECT_EQ(p.counters().handed_off_filled, 1u);
  EXPECT_EQ(p.counters().handed_off_overfilled, 1u);
  EXPECT_EQ(p.counters().handed_off_underfilled, 1u);
}

TEST(Plant, LongRunStaysBoundedAndCountsEveryBottle) {
  PlantConfig c;
  c.bottle_spacing_mm = 67;  // densest belt the checks allow: 15 bottles on 1 m
  Plant p{c};
  uint8_t most = 0;
  for (uint32_t i = 0; i < 100000; ++i) {
    p.step(kMove);
    if (p.bottle_count() > most) most = p.bottle_count();
  }
  EXPECT_EQ(most, 15u);
  EXPECT_LE(most, kMaxBottles);
  // 100 m of belt: every bottle that came in is on the belt or handed on.
  EXPECT_EQ(p.counters().bottles_in, p.counters().handed_off + p.bottle_count());
  EXPECT_EQ(p.counters().handed_off, 100000u * 1000u / 67000u - 14u);
  EXPECT_EQ(p.counters().handed_off_underfilled, p.counters().handed_off);
}

TEST(Plant, BeltShorterThanSpacingRefillsFromTheStart) {
  PlantConfig c;
  c.conveyor_length_mm = 300;
  c.valve_position_mm = 150;
  c.bottle_spacing_mm = 400;
  Plant p{c};
  run(p, kMove, 300);
  EXPECT_EQ(p.counters().handed_off, 1u);
  ASSERT_EQ(p.bottle_count(), 1u);
  EXPECT_EQ(p.bottle(0).position_um, 0u);
}

TEST(Plant, ResetRestoresTheInitialState) {
  Plant p{PlantConfig()};
  run(p, kMove, 700);
  run(p, kPour, 10);
  p.reset();
  EXPECT_EQ(p.steps(), 0u);
  ASSERT_EQ(p.bottle_count(), 1u);
  EXPECT_EQ(p.bottle(0).position_um, 0u);
  EXPECT_EQ(p.counters().spilled_ul, 0u);
  EXPECT_EQ(p.counters().bottles_in, 1u);
}

TEST(Plant, SameInputsGiveIdenticalStates) {
  PlantConfig c;
  c.conveyor_speed_mm_s = 333;
  c.fill_flow_ml_s = 77;
  Plant a{c};
  Plant b{c};
  uint32_t x = 12345;
  for (uint32_t i = 0; i < 20000; ++i) {
    x = x * 1103515245u + 12345u;  // fixed pseudo-random actuator pattern
    const Actuators act{(x >> 16 & 3u) != 0u, (x >> 20 & 7u) == 0u};
    a.step(act);
    b.step(act);
  }
  ASSERT_EQ(a.bottle_count(), b.bottle_count());
  for (uint8_t i = 0; i < a.bottle_count(); ++i) {
    EXPECT_EQ(a.bottle(i).position_um, b.bottle(i).position_um);
    EXPECT_EQ(a.bottle(i).level_ul, b.bottle(i).level_ul);
  }
  EXPECT_EQ(a.counters().spilled_ul, b.counters().spilled_ul);
  EXPECT_EQ(a.counters().handed_off, b.counters().handed_off);
  EXPECT_GT(a.counters().handed_off, 0u);
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
