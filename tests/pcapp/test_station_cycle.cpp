#include <gtest/gtest.h>

#include "fake_gateway.h"
#include "gateway/line_app.h"
#include "station_cycle.h"

using namespace mb2co;
using namespace mb2co::pcapp;
using plant::State;

namespace {
struct StationCycleTest : ::testing::Test {
  FakeGateway gw;
  plant::PlantConfig config;
  StationCycle station{gw.layout, config};

  void cycle() { station.step(gw.in, gw.out); }
  void click(gateway::Button b) {
    gw.set(Field::kInputs, b);
    cycle();
    gw.set(Field::kInputs, 0);
  }
  void start() {
    cycle();                                          // baseline of START
    EXPECT_EQ(station.take_event(), "buttons none");  // the first read shows the panel
    click(gateway::kStart);
    ASSERT_EQ(station.controller().state(), State::kMoving);
    EXPECT_EQ(station.take_event(), "buttons START\nstate moving");
    cycle();
    EXPECT_EQ(station.take_event(), "buttons none");
  }
  /// The "state ..." line of the last step's events.
  std::string state_event() {
    const std::string e = station.take_event();
    const size_t at = e.find("state ");
    return at == std::string::npos ? std::string() : e.substr(at);
  }
};
}  // namespace

TEST_F(StationCycleTest, StartWritesRunAndTheBeltMoves) {
  start();
  EXPECT_EQ(gw.written(Field::kRunCommand), 1u);
  const uint32_t before = station.plant().bottle(0).position_um;
  cycle();
  EXPECT_GT(station.plant().bottle(0).position_um, before);
}

TEST_F(StationCycleTest, Stop2CounterStopsInTheSameCycle) {
  start();
  gw.set(Field::kStop2Count, 1);
  cycle();
  EXPECT_EQ(station.controller().state(), State::kStopped);
  EXPECT_EQ(gw.written(Field::kRunCommand), 0u);
  EXPECT_EQ(state_event(), "state stopped cause=local_stop2");
  EXPECT_FALSE(station.controller().outputs().plant.motor_on);
}

TEST_F(StationCycleTest, PreviousStationStop2Stops) {
  start();
  gw.set(Field::kPrevStop2, 4);
  cycle();
  EXPECT_EQ(state_event(), "state stopped cause=prev_stop2");
}

TEST_F(StationCycleTest, OldStopCauseRightAfterStartIsNoNewStop) {
  gw.set(Field::kStopCause, gateway::kCauseStopButton);  // from an earlier stop
  cycle();
  click(gateway::kStart);  // RUN=1 written at the end of this cycle
  ASSERT_TRUE(station.controller().running());
  cycle();  // the firmware has not applied RUN=1 before this read: run_state 0, cause 1
  EXPECT_TRUE(station.controller().running());
  // Once RUN=1 was written two cycles ago, the same picture is a latched STOP.
  cycle();
  EXPECT_EQ(station.controller().state(), State::kStopped);
  EXPECT_EQ(state_event(), "state stopped cause=stop_button");
}

TEST_F(StationCycleTest, LinkLossIsSafeAndNeedsAFreshStart) {
  start();
  gw.set(Field::kRunState, 1);
  cycle();
  station.link_lost();
  EXPECT_EQ(state_event(), "state stopped cause=link_lost");
  const uint32_t at = station.plant().bottle(0).position_um;
  station.step_offline();
  EXPECT_EQ(station.plant().bottle(0).position_um, at);
  station.safe_outputs(gw.out);
  EXPECT_EQ(gw.written(Field::kRunCommand), 0u);
  gw.set(Field::kInputs, gateway::kStart);  // START held across the outage: no press
  cycle();
  EXPECT_EQ(station.take_event(), "buttons START");  // the panel again after the outage
  EXPECT_EQ(station.controller().state(), State::kStopped);
  gw.set(Field::kInputs, 0);
  cycle();
  click(gateway::kStart);
  EXPECT_TRUE(station.controller().running());
}

TEST_F(StationCycleTest, FillsBottlesInClosedLoop) {
  start();
  gw.set(Field::kRunState, 1);
  // Default plant with a 10 ms step: 2 s to the valve, 5 s of filling.
  for (int i = 0; i < 1000; ++i) cycle();
  EXPECT_EQ(station.controller().counters().bottles_filled, 1u);
  EXPECT_EQ(station.plant().counters().spilled_ul, 0u);
}

TEST_F(StationCycleTest, LogColumnsMatchTheNames) {
  start();
  std::vector<LogValue> row;
  station.columns(row);
  EXPECT_EQ(row.size(), station.column_names().size());
  EXPECT_NE(station.status().find("station moving"), std::string::npos);
  EXPECT_NE(station.summary().find("starts=1"), std::string::npos);
}
