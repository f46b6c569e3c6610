// Error control (CiA 301 §7.2.8.3): heartbeat producer 1017h, heartbeat
// consumer 1016h with its events and EMCY 8130h, node guarding with toggle
// bit and life guarding (100Ch × 100Dh).
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Heartbeat = IoNodeTest;

/// Times (ms since the first one) of the frames with `id` in the next `ms`.
std::vector<uint32_t> frame_times(Harness& h, uint32_t id, uint32_t ms) {
  std::vector<uint32_t> at;
  const uint32_t t0 = h.now;
  for (uint32_t i = 0; i < ms * 10; ++i) {  // 100 µs steps
    h.advance_us(100);
    for (const CanFrame& f : h.take_frames()) {
      if (f.id == id) at.push_back((h.now - t0) / 1000);
    }
  }
  return at;
}

TEST_F(Heartbeat, ProducerSendsTheStateEveryPeriod) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);
  EXPECT_EQ(frame_times(h, 0x703, 450), std::vector<uint32_t>({100, 200, 300, 400}));
  h.advance_us(50000);
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  operational();
  h.run_us(100000);
  EXPECT_EQ(h.take(), Frames({"<703> 05"}));
  h.nmt(0x02, kId);
  h.run_us(100000);
  EXPECT_EQ(h.take(), Frames({"<703> 04"})) << "the heartbeat continues in stopped";
}

TEST_F(Heartbeat, WritingThePeriodRestartsTheTimer) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);
  h.run_us(70000);
  ASSERT_EQ(h.write_u16(0x1017, 0, 200), 0u);
  EXPECT_EQ(frame_times(h, 0x703, 650), std::vector<uint32_t>({200, 400, 600}));
  // Writing the same value restarts it too.
  h.run_us(50000);  // 700 - 600 = 100 ms since the last one... now 150
  ASSERT_EQ(h.write_u16(0x1017, 0, 200), 0u);
  EXPECT_EQ(frame_times(h, 0x703, 250), std::vector<uint32_t>({200}));
  // 0 stops it.
  ASSERT_EQ(h.write_u16(0x1017, 0, 0), 0u);
  EXPECT_TRUE(frame_times(h, 0x703, 1000).empty());
}

TEST_F(Heartbeat, NoBurstAfterAPause) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 10), 0u);
  h.advance_us(10000);
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  h.advance_us(1000000);  // the caller was blocked for a second
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  h.advance_us(9000);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
}

// ---- consumer ---------------------------------------------------------------
struct HbEventLog {
  struct Ev {
    uint8_t node;
    HbEvent event;
    uint8_t state;
    bool operator==(const Ev& o) const { return node == o.node && event == o.event && state == o.state; }
  };
  std::vector<Ev> events;
  static void cb(void* ctx, uint8_t node, HbEvent e, uint8_t state) {
    static_cast<HbEventLog*>(ctx)->events.push_back({node, e, state});
  }
};

class HeartbeatConsumerTest : public IoNodeTest {
 protected:
  void SetUp() override {
    IoNodeTest::SetUp();
    io.node().heartbeat_consumer().set_callback(&HbEventLog::cb, &log);
  }
  std::vector<HbEventLog::Ev> take_events() {
    std::vector<HbEventLog::Ev> e = log.events;
    log.events.clear();
    return e;
  }
  HbEventLog log;
};

using Ev = HbEventLog::Ev;

TEST_F(HeartbeatConsumerTest, StartedStateChangeLostAndRecovery) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);  // node 5, 100 ms
  HeartbeatConsumer& hb = io.node().heartbeat_consumer();
  EXPECT_EQ(hb.remote_state(5), kHbUnknown);
  h.run_us(500000, 1000);  // nothing heard yet: no timeout before the first heartbeat
  EXPECT_TRUE(take_events().empty());
  EXPECT_EQ(h.take(), Frames({}));

  h.rx(F(0x705, {0x7F}));
  EXPECT_EQ(take_events(), std::vector<Ev>({{5, kHbStarted, 0x7F}}));
  EXPECT_EQ(hb.remote_state(5), kHbActive);
  h.run_us(90000, 1000);
  h.rx(F(0x705, {0x7F}));
  EXPECT_TRUE(take_events().empty()) << "same state: no event";
  h.run_us(90000, 1000);
  h.rx(F(0x705, {0x05}));
  EXPECT_EQ(take_events(), std::vector<Ev>({{5, kHbStateChanged, 0x05}}));
  EXPECT_EQ(hb.remote_nmt(5), 0x05);
  h.run_us(99000, 1000);
  EXPECT_TRUE(take_events().empty());
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);  // 100 ms after the last heartbeat
  EXPECT_EQ(take_events(), std::vector<Ev>({{5, kHbLost, 0x05}}));
  EXPECT_EQ(hb.remote_state(5), kHbTimeout);
  EXPECT_EQ(h.take(), Frames({"<083> 30 81 11 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1001, 0), 0x11u);
  EXPECT_EQ(h.read(0x1003, 1), 0x8130u);
  h.run_us(1000000, 10000);
  EXPECT_TRUE(take_events().empty()) << "lost once";
  EXPECT_EQ(h.take(), Frames({}));

  h.rx(F(0x705, {0x05}));
  EXPECT_EQ(take_events(), std::vector<Ev>({{5, kHbStarted, 0x05}}));
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"})) << "error reset";
  EXPECT_EQ(h.read(0x1001, 0), 0u);
}

TEST_F(HeartbeatConsumerTest, BootUpOfTheRemoteIsReported) {
  ASSERT_EQ(h.write_u32(0x1016, 2, 0x000A00C8u), 0u);  // node 10, 200 ms
  h.rx(F(0x70A, {0x05}));
  h.rx(F(0x70A, {0x00}));
  EXPECT_EQ(take_events(), std::vector<Ev>({{10, kHbStarted, 0x05}, {10, kHbBootUp, 0x00}}));
  EXPECT_EQ(io.node().heartbeat_consumer().remote_state(10), kHbUnknown);
  // After a boot-up the monitor waits for the first heartbeat again.
  h.run_us(1000000, 10000);
  EXPECT_TRUE(take_events().empty());
  h.rx(F(0x70A, {0x7F}));
  EXPECT_EQ(take_events(), std::vector<Ev>({{10, kHbStarted, 0x7F}}));
}

TEST_F(HeartbeatConsumerTest, FourConsumersAreIndependent) {
  for (uint8_t s = 1; s <= 4; ++s) {
    ASSERT_EQ(h.write_u32(0x1016, s, (static_cast<uint32_t>(s + 10) << 16) | (100u * s)), 0u);
  }
  for (uint8_t n = 11; n <= 14; ++n) h.rx(F(0x700u + n, {0x05}));
  EXPECT_EQ(take_events().size(), 4u);
  h.run_us(100000, 1000);
  EXPECT_EQ(take_events(), std::vector<Ev>({{11, kHbLost, 0x05}}));
  EXPECT_EQ(h.take(), Frames({"<083> 30 81 11 00 00 00 00 00"}));
  h.run_us(100000, 1000);
  EXPECT_EQ(take_events(), std::vector<Ev>({{12, kHbLost, 0x05}}));
  EXPECT_EQ(h.take(), Frames({})) << "8130h is already active";
  h.rx(F(0x70B, {0x05}));
  h.rx(F(0x70C, {0x05}));
  EXPECT_EQ(take_events().size(), 2u);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
  // Another node's heartbeat has no effect on them.
  h.rx(F(0x715, {0x05}));
  EXPECT_TRUE(take_events().empty());
  // 300 ms: node 11 (100 ms after its heartbeat at 200) and node 13 (300 ms).
  h.run_us(100000, 1000);
  EXPECT_EQ(take_events(), std::vector<Ev>({{11, kHbLost, 0x05}, {13, kHbLost, 0x05}}));
  EXPECT_EQ(h.take(), Frames({"<083> 30 81 11 00 00 00 00 00"}));
  // 400 ms: node 12 (200 ms after 200) and node 14 (400 ms).
  h.run_us(100000, 1000);
  EXPECT_EQ(take_events(), std::vector<Ev>({{12, kHbLost, 0x05}, {14, kHbLost, 0x05}}));
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(HeartbeatConsumerTest, WrongLengthAndRtrFramesAreNoHeartbeats) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);
  for (uint8_t dlc = 0; dlc <= 8; ++dlc) {
    if (dlc == 1) continue;
    CanFrame f = F(0x705, {0x05, 0x05, 0x05, 0x05, 0x05, 0x05, 0x05, 0x05});
    f.dlc = dlc;
    h.rx(f);
  }
  h.rx(Rtr(0x705, 1));
  EXPECT_TRUE(take_events().empty());
  EXPECT_EQ(io.node().heartbeat_consumer().remote_state(5), kHbUnknown);
}

TEST_F(HeartbeatConsumerTest, NotMonitoredInStoppedAndUnconfiguredByZero) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);
  h.rx(F(0x705, {0x05}));
  take_events();
  h.nmt(0x02, kId);
  h.run_us(1000000, 10000);
  EXPECT_TRUE(take_events().empty());
  EXPECT_EQ(h.take(), Frames({}));
  h.nmt(0x80, kId);
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050000u), 0u);  // time 0: off
  h.rx(F(0x705, {0x05}));
  h.run_us(1000000, 10000);
  EXPECT_TRUE(take_events().empty());
  EXPECT_EQ(io.node().heartbeat_consumer().remote_state(5), kHbUnconfigured);
}

TEST_F(HeartbeatConsumerTest, ReconfiguringALostConsumerClearsTheError) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);
  h.rx(F(0x705, {0x05}));
  h.run_us(100000, 1000);
  EXPECT_EQ(h.take(), Frames({"<083> 30 81 11 00 00 00 00 00"}));
  ASSERT_EQ(h.write_u32(0x1016, 1, 0u), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1001, 0), 0u);
}

// ---- node guarding -------------------------------------------------------------
using Guarding = IoNodeTest;

TEST_F(Guarding, AnswersWithTheStateAndAToggleBit) {
  h.rx(Rtr(0x703));
  h.rx(Rtr(0x703));
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> 7F", "<703> FF", "<703> 7F"}));
  operational();
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> 85"}));
  h.nmt(0x02, kId);
  h.rx(Rtr(0x703));
  h.rx(Rtr(0x703, 1));  // a DLC in the request does not matter
  EXPECT_EQ(h.take(), Frames({"<703> 04", "<703> 84"}));
  // Reset communication starts the toggle at 0 again.
  h.nmt(0x82, kId);
  h.take();
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
}

TEST_F(Guarding, DataFramesOnTheErrorControlIdAreIgnored) {
  for (uint8_t dlc = 0; dlc <= 8; ++dlc) {
    CanFrame f = F(0x703, {0x7F, 0, 0, 0, 0, 0, 0, 0});
    f.dlc = dlc;
    h.rx(f);
  }
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Guarding, NotAnsweredWhileAHeartbeatIsProduced) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 1000), 0u);
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({}));
  ASSERT_EQ(h.write_u16(0x1017, 0, 0), 0u);
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
}

TEST_F(Guarding, LifeGuardingTimeoutRaisesEmcyAndTheNextRequestClearsIt) {
  ASSERT_EQ(h.write_u16(0x100C, 0, 100), 0u);
  ASSERT_EQ(h.write_u8(0x100D, 0, 3), 0u);
  h.run_us(1000000, 1000);
  EXPECT_EQ(h.take(), Frames({})) << "life guarding starts with the first request";
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  h.run_us(299000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);  // 100 ms × 3
  EXPECT_EQ(h.take(), Frames({"<083> 30 81 11 00 00 00 00 00"}));
  h.run_us(1000000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(Rtr(0x703));
  EXPECT_EQ(h.take(), Frames({"<703> FF", "<083> 00 00 00 00 00 00 00 00"}));
  // Regular requests keep it quiet.
  for (int i = 0; i < 10; ++i) {
    h.run_us(250000, 1000);
    h.rx(Rtr(0x703));
  }
  EXPECT_EQ(h.take().size(), 10u);
}

TEST_F(Guarding, LifeGuardingOffWhenGuardTimeOrFactorIsZero) {
  ASSERT_EQ(h.write_u16(0x100C, 0, 100), 0u);
  h.rx(Rtr(0x703));
  h.run_us(2000000, 10000);
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  ASSERT_EQ(h.write_u16(0x100C, 0, 0), 0u);
  ASSERT_EQ(h.write_u8(0x100D, 0, 3), 0u);
  h.run_us(2000000, 10000);
  EXPECT_EQ(h.take(), Frames({}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
