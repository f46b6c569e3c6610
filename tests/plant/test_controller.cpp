// The controller alone, fed hand-made inputs: every transition of the state
// machine, stop causes, STOP2 counters, force_safe().
#include <gtest/gtest.h>

#include <string>

#include "plant/controller.h"

namespace mb2co {
namespace plant {
namespace {

ControllerConfig test_config(uint32_t approach = 3, uint32_t timeout = 50, bool at_valve = true) {
  ControllerConfig c;
  c.approach_steps = approach;
  c.fill_timeout_steps = timeout;
  c.sensor_at_valve = at_valve;
  return c;
}

bool safe(const ControllerOutputs& out) {
  return out.run == RunState::kStopped && !out.plant.motor_on && !out.plant.valve_open;
}

// A controller plus the inputs it is fed; helpers move it to each state.
struct Rig {
  explicit Rig(const ControllerConfig& config = test_config()) : ctl(config) {}

  const ControllerOutputs& cycle() { return ctl.step(in); }

  void start() {
    in.start_pressed = true;
    cycle();
    in.start_pressed = false;
    cycle();
  }
  /// START released for a cycle, then pressed (and kept pressed).
  void release_and_press_start() {
    in.start_pressed = false;
    cycle();
    in.start_pressed = true;
    cycle();
  }
  void to_moving() {
    cycle();  // baselines
    start();
    ASSERT_EQ(ctl.state(), State::kMoving);
  }
  void to_approach() {
    to_moving();
    in.plant.bottle_present = true;
    cycle();
    ASSERT_EQ(ctl.state(), State::kApproach);
  }
  void to_filling() {
    to_approach();
    while (ctl.state() == State::kApproach) cycle();
    ASSERT_EQ(ctl.state(), State::kFilling);
  }
  void to_state(State s) {
    if (s == State::kMoving) to_moving();
    if (s == State::kApproach) to_approach();
    if (s == State::kFilling) to_filling();
  }

  Controller ctl;
  ControllerInputs in;
};

class ControllerTest : public ::testing::Test, public Rig {};

TEST_F(ControllerTest, StartsStoppedAndSafe) {
  EXPECT_EQ(ctl.state(), State::kStopped);
  EXPECT_TRUE(safe(ctl.outputs()));
  EXPECT_TRUE(safe(cycle()));
  EXPECT_FALSE(ctl.outputs().lamp_fault);
  EXPECT_EQ(ctl.fault(), Fault::kNone);
}

TEST_F(ControllerTest, StartPressRunsTheBelt) {
  cycle();
  in.start_pressed = true;
  const ControllerOutputs& out = cycle();
  EXPECT_EQ(ctl.state(), State::kMoving);
  EXPECT_EQ(out.run, RunState::kRunning);
  EXPECT_TRUE(out.plant.motor_on);
  EXPECT_FALSE(out.plant.valve_open);
  EXPECT_EQ(ctl.counters().starts, 1u);
  in.start_pressed = false;
  EXPECT_EQ(cycle().run, RunState::kRunning);  // START is a press, not a hold
}

TEST_F(ControllerTest, StartHeldAtTheFirstSampleIsNoPress) {
  in.start_pressed = true;
  cycle();
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
  release_and_press_start();
  EXPECT_EQ(ctl.state(), State::kMoving);
}

TEST_F(ControllerTest, StartStillHeldAfterAStopDoesNotRestart) {
  cycle();
  in.start_pressed = true;
  cycle();
  in.stop_pressed = true;
  cycle();
  in.stop_pressed = false;
  cycle();
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
  EXPECT_EQ(ctl.counters().starts, 1u);
}

TEST_F(ControllerTest, StopInputsBeatAStartPressInTheSameCycle) {
  struct Case {
    const char* name;
    void (*apply)(ControllerInputs&);
  };
  const Case cases[] = {
      {"STOP held", [](ControllerInputs& i) { i.stop_pressed = true; }},
      {"STOP2 held", [](ControllerInputs& i) { i.stop2_pressed = true; }},
      {"local STOP2 event", [](ControllerInputs& i) { ++i.local_stop2_events; }},
      {"previous STOP2 event", [](ControllerInputs& i) { ++i.prev_stop2_events; }},
  };
  for (const Case& c : cases) {
    Controller fresh(test_config());
    ControllerInputs i;
    fresh.step(i);
    i.start_pressed = true;
    c.apply(i);
    EXPECT_TRUE(safe(fresh.step(i))) << c.name;
    EXPECT_EQ(fresh.state(), State::kStopped) << c.name;
    EXPECT_EQ(fresh.counters().starts, 0u) << c.name;
  }
}

TEST_F(ControllerTest, MovingToApproachOnTheSensorsRisingEdge) {
  to_moving();
  cycle();
  EXPECT_EQ(ctl.state(), State::kMoving);
  in.plant.bottle_present = true;
  const ControllerOutputs& out = cycle();
  EXPECT_EQ(ctl.state(), State::kApproach);
  EXPECT_TRUE(out.plant.motor_on);  // first of the 3 approach steps
  EXPECT_FALSE(out.plant.valve_open);
}

TEST_F(ControllerTest, ABottleAlreadyAtTheSensorWhenStartingIsNotFilled) {
  in.plant.bottle_present = true;  // unknown bottle, unknown alignment
  cycle();
  start();
  cycle();
  EXPECT_EQ(ctl.state(), State::kMoving);
  in.plant.bottle_present = false;
  cycle();
  in.plant.bottle_present = true;  // the next one is ours
  cycle();
  EXPECT_EQ(ctl.state(), State::kApproach);
}

TEST_F(ControllerTest, ApproachRunsExactlyApproachStepsThenFills) {
  to_moving();
  in.plant.bottle_present = true;
  int motor_cycles = 0;
  for (;;) {
    const ControllerOutputs& out = cycle();
    if (!out.plant.motor_on) break;
    ++motor_cycles;
    ASSERT_LT(motor_cycles, 100);
  }
  EXPECT_EQ(motor_cycles, 3);
  EXPECT_EQ(ctl.state(), State::kFilling);
  EXPECT_TRUE(ctl.outputs().plant.valve_open);
  EXPECT_EQ(ctl.outputs().run, RunState::kRunning);
}

TEST(ControllerNoApproach, MovingToFillingInTheSameCycle) {
  Controller ctl(test_config(0));
  ControllerInputs in;
  ctl.step(in);
  in.start_pressed = true;
  ctl.step(in);
  in.plant.bottle_present = true;
  const ControllerOutputs& out = ctl.step(in);
  EXPECT_EQ(ctl.state(), State::kFilling);
  EXPECT_FALSE(out.plant.motor_on);
  EXPECT_TRUE(out.plant.valve_open);
}

TEST_F(ControllerTest, FillingToMovingWhenFull) {
  to_filling();
  cycle();
  EXPECT_TRUE(ctl.outputs().plant.valve_open);
  in.plant.level_full = true;
  const ControllerOutputs& out = cycle();
  EXPECT_EQ(ctl.state(), State::kMoving);
  EXPECT_FALSE(out.plant.valve_open);  // closed in the cycle "full" is seen
  EXPECT_TRUE(out.plant.motor_on);
  EXPECT_EQ(ctl.counters().bottles_filled, 1u);
  // The filled bottle still at the sensor is no new edge.
  in.plant.level_full = false;
  cycle();
  EXPECT_EQ(ctl.state(), State::kMoving);
}

TEST_F(ControllerTest, FillingToFaultWhenTheBottleIsLost) {
  to_filling();
  in.plant.bottle_present = false;
  const ControllerOutputs& out = cycle();
  EXPECT_EQ(ctl.state(), State::kFault);
  EXPECT_EQ(ctl.fault(), Fault::kBottleLost);
  EXPECT_TRUE(safe(out));
  EXPECT_TRUE(out.lamp_fault);
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kFault)], 1u);
}

TEST(ControllerSensorUpstream, LosingTheSensorWhileFillingIsNormal) {
  Controller ctl(test_config(3, 50, false));
  ControllerInputs in;
  ctl.step(in);
  in.start_pressed = true;
  ctl.step(in);
  in.plant.bottle_present = true;
  for (int i = 0; i < 4; ++i) ctl.step(in);
  ASSERT_EQ(ctl.state(), State::kFilling);
  in.plant.bottle_present = false;  // the bottle left the upstream sensor
  ctl.step(in);
  EXPECT_EQ(ctl.state(), State::kFilling);
  EXPECT_TRUE(ctl.outputs().plant.valve_open);
}

TEST_F(ControllerTest, FillingToFaultAfterExactlyTheTimeout) {
  to_filling();  // the first valve-open cycle is done
  for (uint32_t i = 1; i < 50; ++i) {
    ASSERT_TRUE(cycle().plant.valve_open) << i;
  }
  const ControllerOutputs& out = cycle();  // 51st: 50 open cycles were allowed
  EXPECT_EQ(ctl.state(), State::kFault);
  EXPECT_EQ(ctl.fault(), Fault::kFillTimeout);
  EXPECT_TRUE(safe(out));
}

TEST(ControllerOverfill, SwitchWhileRunningIsAFault) {
  for (State s : {State::kMoving, State::kApproach, State::kFilling}) {
    Rig r;
    r.to_state(s);
    r.in.plant.overfill = true;
    EXPECT_TRUE(safe(r.cycle()));
    EXPECT_EQ(r.ctl.state(), State::kFault);
    EXPECT_EQ(r.ctl.fault(), Fault::kOverfill);
    EXPECT_EQ(r.ctl.counters().overfills, 1u);
    r.cycle();  // still high: one overfill, not two
    EXPECT_EQ(r.ctl.counters().overfills, 1u);
  }
}

TEST_F(ControllerTest, FaultWaitsForStartThenResumesMoving) {
  to_filling();
  in.plant.bottle_present = false;
  cycle();
  ASSERT_EQ(ctl.state(), State::kFault);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(safe(cycle()));
  start();
  EXPECT_EQ(ctl.state(), State::kMoving);  // not refilling the faulty bottle
  EXPECT_EQ(ctl.fault(), Fault::kNone);
  EXPECT_FALSE(ctl.outputs().lamp_fault);
  EXPECT_EQ(ctl.counters().starts, 2u);
}

// Every running state x every operator stop input: safe in that same cycle,
// counted under its cause, and START resumes the very state.
struct StopCase {
  State state;
  StopCause cause;
};

std::string stop_case_name(const ::testing::TestParamInfo<StopCase>& param) {
  static const char* const kStates[] = {"stopped", "fault", "moving", "approach", "filling"};
  static const char* const kCauses[] = {"stop_button", "local_stop2", "prev_stop2", "link_lost", "fault"};
  return std::string(kStates[static_cast<int>(param.param.state)]) + "_" +
         kCauses[static_cast<int>(param.param.cause)];
}

class ControllerStopTest : public ControllerTest, public ::testing::WithParamInterface<StopCase> {};

TEST_P(ControllerStopTest, SafeInTheCycleTheStopIsSeenAndResumesExactly) {
  const StopCase p = GetParam();
  to_state(p.state);
  switch (p.cause) {
    case StopCause::kStopButton:
      in.stop_pressed = true;
      break;
    case StopCause::kLocalStop2:
      in.stop2_pressed = true;
      ++in.local_stop2_events;
      break;
    case StopCause::kPrevStop2:
      in.prev_stop2_events = static_cast<uint16_t>(in.prev_stop2_events + 1u);
      break;
    case StopCause::kLinkLost:
      break;
    case StopCause::kFault:
      FAIL();
  }
  const ControllerOutputs& out = p.cause == StopCause::kLinkLost ? ctl.force_safe() : cycle();
  EXPECT_TRUE(safe(out));
  EXPECT_EQ(ctl.state(), State::kStopped);
  for (uint8_t c = 0; c < kStopCauseCount; ++c) {
    EXPECT_EQ(ctl.counters().stops[c], c == static_cast<uint8_t>(p.cause) ? 1u : 0u) << int(c);
  }
  in.stop_pressed = false;
  in.stop2_pressed = false;
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(safe(cycle()));
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(p.cause)], 1u);  // once, not per cycle
  start();
  EXPECT_EQ(ctl.state(), p.state);
}

INSTANTIATE_TEST_SUITE_P(EveryRunningState, ControllerStopTest,
                         ::testing::Values(StopCase{State::kMoving, StopCause::kStopButton},
                                           StopCase{State::kMoving, StopCause::kLocalStop2},
                                           StopCase{State::kMoving, StopCause::kPrevStop2},
                                           StopCase{State::kMoving, StopCause::kLinkLost},
                                           StopCase{State::kApproach, StopCause::kStopButton},
                                           StopCase{State::kApproach, StopCause::kLocalStop2},
                                           StopCase{State::kApproach, StopCause::kPrevStop2},
                                           StopCase{State::kApproach, StopCause::kLinkLost},
                                           StopCase{State::kFilling, StopCause::kStopButton},
                                           StopCase{State::kFilling, StopCause::kLocalStop2},
                                           StopCase{State::kFilling, StopCause::kPrevStop2},
                                           StopCase{State::kFilling, StopCause::kLinkLost}),
                         stop_case_name);

TEST_F(ControllerTest, ABottleReachingTheSensorInTheStopCycleIsNotLost) {
  to_moving();
  in.plant.bottle_present = true;  // the edge and the STOP in the same cycle
  in.stop_pressed = true;
  EXPECT_TRUE(safe(cycle()));
  in.stop_pressed = false;
  cycle();
  in.start_pressed = true;  // the sensor stays high: no new edge will come
  cycle();
  EXPECT_EQ(ctl.state(), State::kApproach);
  in.start_pressed = false;
  int motor_cycles = 1;
  while (cycle().plant.motor_on) ++motor_cycles;
  EXPECT_EQ(motor_cycles, 3);  // the whole approach, none taken while stopped
  EXPECT_EQ(ctl.state(), State::kFilling);
}

TEST_F(ControllerTest, ABottleSeenFirstAfterALinkOutageIsNotLost) {
  to_moving();
  ctl.force_safe();  // the belt's last step brought a bottle to the sensor...
  in.plant.bottle_present = true;
  cycle();  // ...seen at the first poll after the outage
  EXPECT_EQ(ctl.state(), State::kStopped);
  start();
  EXPECT_EQ(ctl.state(), State::kApproach);
}

TEST_F(ControllerTest, ResumedApproachKeepsTheStepsLeft) {
  to_approach();  // 1 of 3 approach steps done
  in.stop_pressed = true;
  cycle();
  in.stop_pressed = false;
  start();  // the START cycle runs approach step 2, the release cycle step 3
  EXPECT_EQ(ctl.state(), State::kApproach);
  EXPECT_TRUE(ctl.outputs().plant.motor_on);
  cycle();
  EXPECT_EQ(ctl.state(), State::kFilling);
}

TEST_F(ControllerTest, ResumedFillingKeepsTheTimeUsed) {
  to_filling();
  for (int i = 0; i < 29; ++i) cycle();  // 30 open cycles
  in.stop_pressed = true;
  cycle();
  in.stop_pressed = false;
  for (int i = 0; i < 100; ++i) cycle();  // stopped time does not count
  start();                                // 32 open cycles
  for (int i = 0; i < 18; ++i) ASSERT_EQ(cycle().plant.valve_open, true);
  cycle();
  EXPECT_EQ(ctl.fault(), Fault::kFillTimeout);
}

TEST_F(ControllerTest, StopWhileStoppedIsNotCounted) {
  cycle();
  in.stop_pressed = true;
  cycle();
  in.stop2_pressed = true;
  ++in.prev_stop2_events;
  cycle();
  for (uint8_t c = 0; c < kStopCauseCount; ++c) EXPECT_EQ(ctl.counters().stops[c], 0u);
  EXPECT_EQ(ctl.counters().prev_stop2_events, 1u);  // the event itself is seen
  ctl.force_safe();
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kLinkLost)], 0u);
}

TEST_F(ControllerTest, OwnStopBeatsStop2InTheCount) {
  to_moving();
  in.stop_pressed = true;
  ++in.local_stop2_events;
  ++in.prev_stop2_events;
  cycle();
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kStopButton)], 1u);
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kLocalStop2)], 0u);
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kPrevStop2)], 0u);
  EXPECT_EQ(ctl.counters().local_stop2_events, 1u);
  EXPECT_EQ(ctl.counters().prev_stop2_events, 1u);
}

TEST_F(ControllerTest, ShortLocalStop2BetweenPollsStopsThroughTheCounter) {
  to_moving();
  in.local_stop2_events = 1;  // press and release both happened between two polls
  EXPECT_TRUE(safe(cycle()));
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kLocalStop2)], 1u);
}

TEST_F(ControllerTest, Stop2HeldKeepsTheStationStopped) {
  cycle();
  in.stop2_pressed = true;
  cycle();
  in.start_pressed = true;
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
}

TEST_F(ControllerTest, PreviousStop2CounterWrapsAndNeverLosesEvents) {
  in.prev_stop2_events = 65534;  // baseline: older events are not ours
  to_moving();
  EXPECT_EQ(ctl.counters().prev_stop2_events, 0u);
  in.prev_stop2_events = 65535;
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
  start();
  in.prev_stop2_events = 0;  // wrapped: one more event
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
  start();
  in.prev_stop2_events = 3;  // three presses between two polls
  cycle();
  EXPECT_EQ(ctl.counters().prev_stop2_events, 5u);
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kPrevStop2)], 3u);
  start();
  for (int i = 0; i < 10; ++i) cycle();  // unchanged counter: keeps running
  EXPECT_TRUE(ctl.running());
}

TEST_F(ControllerTest, ARestartedStop2CounterIsANewBaselineNotThousandsOfEvents) {
  in.prev_stop2_events = 7;
  to_moving();
  in.prev_stop2_events = 0;  // the gateway rebooted: its copy counts from 0 again
  cycle();
  EXPECT_TRUE(ctl.running());
  EXPECT_EQ(ctl.counters().prev_stop2_events, 0u);
  in.prev_stop2_events = 1;  // and the next real event still counts
  cycle();
  EXPECT_EQ(ctl.state(), State::kStopped);
  EXPECT_EQ(ctl.counters().prev_stop2_events, 1u);
}

// Issue 16 item 8: a rebooted gateway shows the previous station's counter
// as 0 until that station's TPDO1 arrives; the PC reads it as not known.
TEST_F(ControllerTest, ACounterNotYetHeardCountsNothingAndTheNextKnownValueCountsOnce) {
  in.prev_stop2_events = 7;
  to_moving();
  in.prev_stop2_events = 0;  // the gateway rebooted: a placeholder, not a value
  in.prev_stop2_known = false;
  for (int i = 0; i < 5; ++i) cycle();
  EXPECT_TRUE(ctl.running()) << "a placeholder is no STOP2 event";
  EXPECT_EQ(ctl.counters().prev_stop2_events, 0u);
  in.prev_stop2_events = 7;  // heard again, unchanged: nothing happened meanwhile
  in.prev_stop2_known = true;
  cycle();
  EXPECT_TRUE(ctl.running());
  EXPECT_EQ(ctl.counters().prev_stop2_events, 0u) << "7 -> 0 -> 7 would count 2^16 - 7 + 7 events";
  in.prev_stop2_events = 0;  // not known again; meanwhile one real press there
  in.prev_stop2_known = false;
  cycle();
  in.prev_stop2_events = 8;
  in.prev_stop2_known = true;
  cycle();
  EXPECT_EQ(ctl.counters().prev_stop2_events, 1u) << "the press during the gap counts once";
  EXPECT_EQ(ctl.state(), State::kStopped);
}

TEST_F(ControllerTest, TheFirstKnownValueIsTheBaseline) {
  in.prev_stop2_known = false;  // the PC starts while the gateway has not heard it
  cycle();
  in.prev_stop2_events = 12;
  in.prev_stop2_known = true;
  to_moving();
  EXPECT_EQ(ctl.counters().prev_stop2_events, 0u) << "events from before are not ours";
  in.prev_stop2_events = 13;
  cycle();
  EXPECT_EQ(ctl.counters().prev_stop2_events, 1u);
  EXPECT_EQ(ctl.state(), State::kStopped);
}

TEST_F(ControllerTest, ForceSafeNeedsAFreshStartPress) {
  to_moving();
  in.start_pressed = true;  // held through the outage
  cycle();
  ctl.force_safe();
  cycle();  // link back, START still held: no press
  EXPECT_EQ(ctl.state(), State::kStopped);
  release_and_press_start();
  EXPECT_EQ(ctl.state(), State::kMoving);
}

TEST_F(ControllerTest, Stop2EventsDuringALinkOutageAreNotLost) {
  to_moving();
  in.prev_stop2_events = 10;
  ctl.force_safe();  // link lost; meanwhile the previous station's STOP2 was pressed
  cycle();           // first poll after the outage sees it
  EXPECT_EQ(ctl.counters().prev_stop2_events, 10u);
  EXPECT_EQ(ctl.counters().stops[static_cast<uint8_t>(StopCause::kLinkLost)], 1u);
}

TEST_F(ControllerTest, ForceSafeKeepsAFault) {
  to_filling();
  in.plant.bottle_present = false;
  cycle();
  EXPECT_TRUE(safe(ctl.force_safe()));
  EXPECT_EQ(ctl.state(), State::kFault);
  EXPECT_TRUE(ctl.outputs().lamp_fault);
}

TEST_F(ControllerTest, NeighbourUnknownLamp) {
  for (NeighbourState prev : {NeighbourState::kAbsent, NeighbourState::kUnknown, NeighbourState::kStopped,
                              NeighbourState::kRunning}) {
    for (NeighbourState next : {NeighbourState::kAbsent, NeighbourState::kUnknown, NeighbourState::kStopped,
                                NeighbourState::kRunning}) {
      in.prev_run = prev;
      in.next_run = next;
      EXPECT_EQ(cycle().lamp_neighbour_unknown,
                prev == NeighbourState::kUnknown || next == NeighbourState::kUnknown);
    }
  }
  EXPECT_EQ(ctl.state(), State::kStopped);  // neighbours never start or stop us
}

TEST(ControllerConfigFor, FollowsThePlant) {
  PlantConfig p;
  ControllerConfig c = controller_config_for(p);
  EXPECT_EQ(c.approach_steps, 10u);
  EXPECT_EQ(c.fill_timeout_steps, 1000u);
  EXPECT_TRUE(c.sensor_at_valve);
  p.sensor_to_valve_mm = 150;
  p.bottle_spacing_mm = 250;
  c = controller_config_for(p);
  EXPECT_EQ(c.approach_steps, 160u);
  EXPECT_FALSE(c.sensor_at_valve);
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
