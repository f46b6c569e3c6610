#include <gtest/gtest.h>

#include "gateway/line_app.h"
#include "station_io.h"

using namespace mb2co;
using namespace mb2co::pcapp;
using plant::NeighbourState;

TEST(StationIo, NeighbourStatesNeverGuessRunning) {
  EXPECT_EQ(neighbour_state(gateway::kNeighbourAlive, 1), NeighbourState::kRunning);
  EXPECT_EQ(neighbour_state(gateway::kNeighbourAlive, 0), NeighbourState::kStopped);
  EXPECT_EQ(neighbour_state(gateway::kNeighbourUnknown, 1), NeighbourState::kUnknown);
  EXPECT_EQ(neighbour_state(gateway::kNeighbourNone, 1), NeighbourState::kAbsent);
  EXPECT_EQ(neighbour_state(7, 1), NeighbourState::kUnknown);
}

TEST(StationIo, DecodesTheDefaultMapIncluding32BitHighWordFirst) {
  const RegisterLayout l = default_layout();
  TransactionPlan p;
  p.read_registers[0] = 14;
  p.read_registers[1] = 23;
  RegisterImage img;
  img.resize(p);
  img.regs[1][0] = gateway::kStart | gateway::kStop2;
  img.regs[1][2] = 65535;
  img.regs[1][7] = 3;
  img.regs[1][12] = 0x1234;
  img.regs[1][13] = 0x5678;
  const Panel panel = decode_panel(l, img);
  EXPECT_EQ(panel.buttons, gateway::kStart | gateway::kStop2);
  EXPECT_EQ(panel.stop2_count, 65535);
  EXPECT_EQ(panel.prev_stop2, 3);
  EXPECT_EQ(img.get(l, Field::kEdgeUs), 0x12345678u);
  img.put(l, Field::kRunCommand, 1);
  EXPECT_EQ(img.regs[0][0], 1);
}

TEST(StationIo, LatchedStopCountsOnlyOnceRunWasConfirmed) {
  Panel p;
  p.run_state = 0;
  p.stop_cause = gateway::kCauseStopButton;
  const plant::Sensors s;
  EXPECT_TRUE(controller_inputs(p, true, s).stop_pressed);
  // Right after START the firmware still shows the old stop: not a new one.
  EXPECT_FALSE(controller_inputs(p, false, s).stop_pressed);
  p.stop_cause = gateway::kCauseStop2Here;  // STOP2 travels as a counter instead
  EXPECT_FALSE(controller_inputs(p, true, s).stop_pressed);
  p.stop_cause = gateway::kCauseStopButton;
  p.run_state = 1;
  EXPECT_FALSE(controller_inputs(p, true, s).stop_pressed);
}

// 80h in a neighbour's status: the gateway has heard no TPDO1 of it since
// its reset, so its RUN state and STOP2 counter are placeholders.
TEST(StationIo, ANotYetHeardNeighbourIsUnknownAndItsCounterNotKnown) {
  Panel p;
  p.prev_stop2 = 0;
  p.prev_run = 0;
  p.prev_status = gateway::kNeighbourAlive | gateway::kNeighbourNotHeard;
  p.next_status = gateway::kNeighbourUnknown | gateway::kNeighbourNotHeard;
  plant::ControllerInputs in = controller_inputs(p, false, plant::Sensors{});
  EXPECT_FALSE(in.prev_stop2_known);
  EXPECT_EQ(in.prev_run, NeighbourState::kUnknown) << "alive, but its RUN state is not heard yet";
  EXPECT_EQ(in.next_run, NeighbourState::kUnknown);
  p.prev_status = gateway::kNeighbourAlive;
  in = controller_inputs(p, false, plant::Sensors{});
  EXPECT_TRUE(in.prev_stop2_known);
  EXPECT_EQ(in.prev_run, NeighbourState::kStopped);
  p.prev_status = gateway::kNeighbourUnknown;  // lost after it was heard: its last values
  EXPECT_TRUE(controller_inputs(p, false, plant::Sensors{}).prev_stop2_known);
}

TEST(StationIo, ButtonsAndCountersReachTheController) {
  Panel p;
  p.buttons = gateway::kStop;
  p.stop2_count = 7;
  p.prev_stop2 = 9;
  p.prev_status = gateway::kNeighbourAlive;
  p.prev_run = 1;
  p.next_status = gateway::kNeighbourNone;
  const plant::ControllerInputs in = controller_inputs(p, false, plant::Sensors{});
  EXPECT_FALSE(in.start_pressed);
  EXPECT_TRUE(in.stop_pressed);
  EXPECT_FALSE(in.stop2_pressed);
  EXPECT_EQ(in.local_stop2_events, 7);
  EXPECT_EQ(in.prev_stop2_events, 9);
  EXPECT_TRUE(in.prev_stop2_known);
  EXPECT_EQ(in.prev_run, NeighbourState::kRunning);
  EXPECT_EQ(in.next_run, NeighbourState::kAbsent);
}
