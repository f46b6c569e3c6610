// The RUN/STOP2 line (seed 000 §10) with real gateways on an in-process bus.
#include <gtest/gtest.h>

#include "line_harness.h"

namespace mb2co {
namespace {

using test::Line;

constexpr uint8_t kStop2 = gateway::kStop2;

void press(Line& line, int i, uint8_t button, uint32_t hold_ms = 60) {
  line.station(i).buttons |= button;
  line.run_ms(hold_ms);
  line.station(i).buttons = static_cast<uint8_t>(line.station(i).buttons & ~button);
}

void set_run_command(Line& line, int i, uint8_t v) {
  ASSERT_EQ(line.gw(i).od().write(0x2100, 1, &v, 1), canopen::kSdoOk);
}

void all_running(Line& line, int n) {
  for (int i = 0; i < n; ++i) set_run_command(line, i, 1);
  line.run_ms(300);
  for (int i = 0; i < n; ++i) ASSERT_EQ(line.od_get(i, 0x2100, 2), 1u) << "station " << i + 1;
}

void ring_of(canopen::ObjectDictionary& od, int n) {
  const uint8_t stations = static_cast<uint8_t>(n);
  ASSERT_EQ(od.write(0x2000, 4, &stations, 1), canopen::kSdoOk);
}

TEST(Line, SelfStartsAndSeesBothNeighboursInARing) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(500);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(line.od_get(i, 0x2002, 0), canopen::kNmtOperational);
    EXPECT_EQ(line.od_get(i, 0x2110, 3), gateway::kNeighbourAlive);
    EXPECT_EQ(line.od_get(i, 0x2120, 3), gateway::kNeighbourAlive);
  }
  EXPECT_EQ(line.od_get(0, 0x2110, 4), 3u);  // node 1: previous is node 3 in a ring
  EXPECT_EQ(line.od_get(0, 0x2120, 4), 2u);
  EXPECT_EQ(line.od_get(2, 0x2120, 4), 1u);
}

TEST(Line, RunLedsShowOwnAndNeighbourStates) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(line.station(i).leds & 0x07,
              gateway::kLedRunSelf | gateway::kLedRunPrev | gateway::kLedRunNext);
  }
}

TEST(Line, Stop2StopsThisAndTheNextStationOnly) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  press(line, 0, kStop2);
  line.run_ms(50);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 0u);
  EXPECT_EQ(line.od_get(0, 0x2100, 4), gateway::kCauseStop2Here);
  EXPECT_EQ(line.od_get(0, 0x2100, 3), 1u);  // STOP2 event counter
  EXPECT_EQ(line.od_get(1, 0x2100, 2), 0u);
  EXPECT_EQ(line.od_get(1, 0x2100, 4), gateway::kCauseStop2Previous);
  EXPECT_EQ(line.od_get(2, 0x2100, 2), 1u);  // node 3 keeps running
  // Node 3 sees both its neighbours stopped.
  EXPECT_EQ(line.station(2).leds & 0x07, gateway::kLedRunSelf);
}

TEST(Line, StopStaysLatchedUntilThePcAcknowledgesWithRunZero) {
  Line line(2, [](canopen::ObjectDictionary& od, int) { ring_of(od, 2); });
  line.run_ms(300);
  all_running(line, 2);
  press(line, 0, gateway::kStop);
  line.run_ms(20);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 0u);
  set_run_command(line, 0, 1);  // a PC still writing 1 does not restart it
  line.run_ms(20);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 0u);
  set_run_command(line, 0, 0);
  set_run_command(line, 0, 1);
  line.run_ms(20);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 1u);
  EXPECT_EQ(line.od_get(0, 0x2100, 4), gateway::kCauseNone);
}

TEST(Line, Stop2ReachesTheNextStationEvenWhenOnePdoIsLost) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  int dropped = 0;
  line.filter = [&](const CanFrame& f, int from) {
    // Drop node 1's first TPDO1 that carries the new STOP2 count.
    if (from == 0 && f.id == 0x181 && f.data[1] == 1 && dropped == 0) {
      ++dropped;
      return false;
    }
    return true;
  };
  press(line, 0, kStop2);
  ASSERT_EQ(dropped, 1);
  EXPECT_EQ(line.od_get(1, 0x2100, 2), 1u) << "the dropped PDO was the only news so far";
  line.run_ms(150);  // TPDO1 event timer (100 ms) repeats the counter
  EXPECT_EQ(line.od_get(1, 0x2100, 2), 0u);
  EXPECT_EQ(line.od_get(1, 0x2100, 4), gateway::kCauseStop2Previous);
}

TEST(Line, ALostNeighbourShowsUnknownAndBlinksNeverRunning) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  line.station(1).powered = false;  // node 2 dies
  const uint32_t died = line.now_us;
  while (line.od_get(0, 0x2120, 3) != gateway::kNeighbourUnknown && line.now_us - died < 1000000)
    line.run_ms(1);
  EXPECT_LE(line.now_us - died, 300000u + 1000u) << "within the heartbeat consumer time (3 x 100 ms)";
  EXPECT_EQ(line.od_get(2, 0x2110, 3), gateway::kNeighbourUnknown);
  // The RUN-next LED of node 1 blinks: both levels within one second.
  bool on = false, off = false;
  for (int k = 0; k < 100; ++k) {
    line.run_ms(10);
    (line.station(0).leds & gateway::kLedRunNext ? on : off) = true;
  }
  EXPECT_TRUE(on && off);
}

TEST(Line, ARebootedPreviousStationDoesNotFakeAStop2) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  press(line, 0, kStop2);  // node 1 counter = 1, node 2 stops
  line.run_ms(100);
  set_run_command(line, 1, 0);
  set_run_command(line, 1, 1);
  line.run_ms(100);
  ASSERT_EQ(line.od_get(1, 0x2100, 2), 1u);
  // Node 1 power-cycles: its counter starts again at 0.
  line.station(0).powered = false;
  line.run_ms(400);
  line.power_on(0);
  line.run_ms(500);
  EXPECT_EQ(line.od_get(1, 0x2100, 2), 1u) << "a counter reset is not a STOP2 event";
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourAlive);
}

// Issue 16 item 8: after a reboot, a gateway's copy of its neighbours' RUN
// state and STOP2 counter is 0 until their TPDO1 comes. Status bit 80h says
// so; a heartbeat alone does not clear it; the first TPDO1 does, and a lost
// heartbeat later does not set it again (the copy holds what was sent).
TEST(Line, ANeighbourNotYetHeardIsFlaggedUntilItsTpdo1) {
  Line line(3, [](canopen::ObjectDictionary& od, int) { ring_of(od, 3); });
  line.run_ms(300);
  all_running(line, 3);
  press(line, 0, kStop2);  // node 1's counter: 1
  line.run_ms(100);
  // Node 2 reboots; node 1's TPDO1 is held back, its heartbeats are not.
  bool hold = true;
  line.filter = [&](const CanFrame& f, int from) { return !(hold && from == 0 && f.id == 0x181); };
  line.station(1).powered = false;
  line.run_ms(50);
  line.power_on(1);
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourUnknown | gateway::kNeighbourNotHeard);
  EXPECT_EQ(line.od_get(1, 0x2120, 3), gateway::kNeighbourUnknown | gateway::kNeighbourNotHeard);
  line.run_ms(300);
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourAlive | gateway::kNeighbourNotHeard)
      << "alive by heartbeat, counter not heard";
  EXPECT_EQ(line.od_get(1, 0x2110, 2), 0u) << "the placeholder the flag warns of";
  EXPECT_EQ(line.od_get(1, 0x2120, 3), gateway::kNeighbourAlive) << "node 3's TPDO1 came";
  // Its LED shows the previous station as unknown (blinks), not as stopped.
  bool on = false, off = false;
  for (int k = 0; k < 60; ++k) {
    line.run_ms(10);
    (line.station(1).leds & gateway::kLedRunPrev ? on : off) = true;
  }
  EXPECT_TRUE(on && off);
  hold = false;
  line.run_ms(150);  // TPDO1 event timer: 100 ms
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourAlive);
  EXPECT_EQ(line.od_get(1, 0x2110, 2), 1u);
  line.station(0).powered = false;  // node 1 lost: unknown, its last values kept
  line.run_ms(400);
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourUnknown);
  EXPECT_EQ(line.od_get(1, 0x2110, 2), 1u);
}

TEST(Line, ChainEndsHaveNoNeighbourThere) {
  Line line(3, [](canopen::ObjectDictionary& od, int) {
    ring_of(od, 3);
    const uint8_t chain = 0;
    ASSERT_EQ(od.write(0x2000, 3, &chain, 1), canopen::kSdoOk);
  });
  line.run_ms(500);
  EXPECT_EQ(line.od_get(0, 0x2110, 3), gateway::kNeighbourNone);
  EXPECT_EQ(line.od_get(0, 0x2110, 4), 0u);
  EXPECT_EQ(line.od_get(2, 0x2120, 3), gateway::kNeighbourNone);
  EXPECT_EQ(line.od_get(1, 0x2110, 3), gateway::kNeighbourAlive);
  // Only the documented COB-IDs appear on the bus.
  for (const auto& s : line.log) {
    const uint32_t node = static_cast<uint32_t>(s.from + 1);
    const uint32_t id = s.frame.id;
    EXPECT_TRUE(id == 0x180 + node || id == 0x280 + node || id == 0x700 + node || id == 0x80 + node)
        << std::hex << id;
  }
}

TEST(Line, ButtonEdgeTimestampIsWhenTheContactMoved) {
  Line line(1, [](canopen::ObjectDictionary& od, int) { ring_of(od, 2); });
  line.run_ms(100);
  const uint32_t pressed_at = line.now_us + 500;  // the next loop sees it
  press(line, 0, gateway::kStart, 40);
  EXPECT_EQ(line.od_get(0, 0x2300, 1), pressed_at);
  EXPECT_EQ(line.od_get(0, 0x2100, 5), 1u);  // START press counter
}

}  // namespace
}  // namespace mb2co

namespace mb2co {
namespace {

TEST(Line, ASilentPcStopsItsStationAfterTheModbusWatchdogTime) {
  test::Line line(1);
  line.run_ms(50);
  uint8_t req[16];
  // The PC's first request arms the watchdog (2000h/9 = 2000 ms by default).
  const uint16_t n = modbus::build_write_single_register(req, sizeof req, 1, 0, 1);
  ASSERT_FALSE(line.modbus(0, req, n).empty());
  line.run_ms(100);
  ASSERT_EQ(line.od_get(0, 0x2100, 2), 1u);
  line.run_ms(1800);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 1u) << "within the watchdog time";
  line.run_ms(200);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 0u);
  EXPECT_EQ(line.od_get(0, 0x2100, 4), gateway::kCausePcSilent);
}

// The watchdog runs from power-on: a station whose PC never comes stops
// like one whose PC fell silent (issue 16: a station never runs by itself).
TEST(Line, WatchdogRunsFromPowerOnWithoutAnyModbusRequest) {
  test::Line line(1);
  uint8_t one = 1;
  ASSERT_EQ(line.gw(0).od().write(0x2100, 1, &one, 1), canopen::kSdoOk);  // by SDO, no PC
  line.run_ms(1900);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 1u);
  line.run_ms(200);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 0u);
  EXPECT_EQ(line.od_get(0, 0x2100, 4), gateway::kCausePcSilent);
}

// A station meant to run without a PC turns the watchdog off (2000h/9 = 0).
TEST(Line, WithoutTheWatchdogAStationRunsWithoutAPc) {
  test::Line line(1, [](canopen::ObjectDictionary& od, int) {
    const uint8_t off[2] = {0, 0};
    ASSERT_EQ(od.write(0x2000, 9, off, 2), canopen::kSdoOk);
  });
  uint8_t one = 1;
  ASSERT_EQ(line.gw(0).od().write(0x2100, 1, &one, 1), canopen::kSdoOk);
  line.run_ms(3000);
  EXPECT_EQ(line.od_get(0, 0x2100, 2), 1u);
}

}  // namespace
}  // namespace mb2co

namespace mb2co {
namespace {

TEST(Line, ARingOfTwoShowsTheOtherStationAsPreviousAndNext) {
  test::Line line(2, [](canopen::ObjectDictionary& od, int) {
    const uint8_t two = 2;
    ASSERT_EQ(od.write(0x2000, 4, &two, 1), canopen::kSdoOk);
  });
  line.run_ms(300);
  uint8_t one = 1;
  for (int i = 0; i < 2; ++i) ASSERT_EQ(line.gw(i).od().write(0x2100, 1, &one, 1), canopen::kSdoOk);
  line.run_ms(300);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(line.station(i).leds & 0x07, gateway::kLedRunSelf | gateway::kLedRunPrev | gateway::kLedRunNext)
        << "station " << i + 1;
  }
}

}  // namespace
}  // namespace mb2co
