// Node::next_deadline (issue 10 item 3), black box: for every timer service,
// process() one microsecond before the deadline it names changes nothing (no
// frame, no OD value, the same deadline), and process() at the deadline does
// the due thing. A service whose timer were missing from next_deadline fails
// its test here (the deadline would be later than its frame, or absent).
#include <gtest/gtest.h>

#include "canopen/clock.h"
#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

class NodeDeadline : public IoNodeTest {
 protected:
  /// The node's next deadline seen from h.now; fails when nothing is pending.
  uint32_t deadline() {
    uint32_t at = 0;
    EXPECT_TRUE(io.node().next_deadline(h.now, &at)) << "no deadline at " << h.now;
    return at;
  }
  bool pending() {
    uint32_t at = 0;
    return io.node().next_deadline(h.now, &at);
  }
  /// Runs process() at `at - 1`, checks that it changed nothing, then at `at`;
  /// returns the frames of that last call.
  Frames run_to(uint32_t at) {
    EXPECT_TRUE(time_reached(at - 1, h.now)) << "deadline " << at << " not ahead of " << h.now;
    const std::vector<Bytes> before = od_snapshot(io.od());
    h.advance_us(at - 1 - h.now);
    EXPECT_EQ(h.take(), Frames{}) << "process() before the deadline sent something";
    EXPECT_EQ(od_snapshot(io.od()), before) << "process() before the deadline changed the OD";
    EXPECT_EQ(deadline(), at) << "the deadline moved";
    h.advance_us(1);
    return h.take();
  }
};

TEST_F(NodeDeadline, NothingPendingInPreOperationalWithoutTimers) {
  h.advance_us(10);
  EXPECT_FALSE(pending());
}

TEST_F(NodeDeadline, HeartbeatProducer) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);  // restarts the timer (process() after it)
  EXPECT_EQ(deadline(), h.now + 100000u);
  EXPECT_EQ(run_to(deadline()), Frames({"<703> 7F"}));
  EXPECT_EQ(deadline(), h.now + 100000u);
}

TEST_F(NodeDeadline, LifeGuarding) {
  ASSERT_EQ(h.write_u16(0x100C, 0, 100), 0u);
  ASSERT_EQ(h.write_u8(0x100D, 0, 3), 0u);
  h.rx(Rtr(0x703, 1));
  EXPECT_EQ(h.take(), Frames({"<703> 7F"}));
  const Frames lost = run_to(h.now + 300000u);
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0].substr(0, 11), "<083> 30 81") << "EMCY 8130h";
}

TEST_F(NodeDeadline, HeartbeatConsumer) {
  ASSERT_EQ(h.write_u32(0x1016, 1, (5u << 16) | 200u), 0u);
  EXPECT_FALSE(pending()) << "nothing heard yet: no consumer time runs";
  h.rx(F(0x705, {0x05}));
  EXPECT_EQ(deadline(), h.now + 200000u);
  const Frames lost = run_to(deadline());
  ASSERT_EQ(lost.size(), 1u);
  EXPECT_EQ(lost[0].substr(0, 11), "<083> 30 81") << "EMCY 8130h";
}

TEST_F(NodeDeadline, SyncProducer) {
  ASSERT_EQ(h.write_u32(0x1006, 0, 10000), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  EXPECT_EQ(run_to(h.now + 10000u), Frames({"<080>"}));
  EXPECT_EQ(run_to(h.now + 10000u), Frames({"<080>"}));
}

TEST_F(NodeDeadline, TpdoEventTimer) {
  ASSERT_EQ(h.write_u16(0x1800, 5, 50), 0u);
  operational();
  h.advance_us(0);
  h.take();
  EXPECT_EQ(run_to(h.now + 50000u), Frames({"<183> 00 00"}));
}

TEST_F(NodeDeadline, TpdoInhibitTime) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u16(0x1800, 3, 1000), 0u);  // 100 ms
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  operational();  // sends TPDO1 at once (the log is cleared)
  const uint32_t sent = h.now;
  h.advance_us(1000);
  io.set_input(0, 0x5A);
  EXPECT_EQ(deadline(), h.now) << "a new value: the TPDOs must look now";
  h.advance_us(0);
  EXPECT_EQ(h.take(), Frames{}) << "inhibited";
  EXPECT_EQ(deadline(), sent + 100000u);
  EXPECT_EQ(run_to(sent + 100000u), Frames({"<183> 5A 00"}));
}

TEST_F(NodeDeadline, RpdoTimeout) {
  ASSERT_EQ(h.write_u16(0x1400, 5, 100), 0u);
  operational();
  h.rx(F(0x203, {0x01, 0x00}));
  h.take();
  const Frames timeout = run_to(h.now + 100000u);
  ASSERT_EQ(timeout.size(), 1u);
  EXPECT_EQ(timeout[0].substr(0, 11), "<083> 50 82") << "EMCY 8250h";
}

TEST_F(NodeDeadline, EmcyInhibitTime) {
  ASSERT_EQ(h.write_u16(0x1015, 0, 1000), 0u);  // 100 ms
  operational();
  h.rx(F(0x203, {0x01}));  // too short: 8210h
  ASSERT_EQ(h.take().size(), 1u);
  const uint32_t first = h.now;
  h.rx(F(0x080, {0x01}));  // SYNC with a counter 1019h does not ask for: 8240h
  EXPECT_EQ(h.take(), Frames{}) << "inhibited";
  const Frames second = run_to(first + 100000u);
  ASSERT_EQ(second.size(), 1u);
  EXPECT_EQ(second[0].substr(0, 11), "<083> 40 82") << "EMCY 8240h";
}

TEST_F(NodeDeadline, ControllerEmcyHoldTime) {
  io.node().on_controller_state(kControllerRxOverflow, false, h.now);
  h.advance_us(0);
  ASSERT_EQ(h.take().size(), 1u);  // 8110h
  const Frames cleared = run_to(h.now + Node::kControllerEventHoldUs);
  ASSERT_EQ(cleared.size(), 1u);
  EXPECT_EQ(cleared[0].substr(0, 11), "<083> 00 00") << "error reset";
}

TEST_F(NodeDeadline, SdoServerTimeout) {
  // A segmented download of 1017h (2 bytes) that never continues.
  EXPECT_EQ(h.sdo({0x21, 0x17, 0x10, 0x00, 0x02, 0x00, 0x00, 0x00}).data[0], 0x60);
  EXPECT_EQ(run_to(h.now + SdoServer::kDefaultTimeoutUs),
            Frames({abort_frame(kId, 0x1017, 0, kAbortTimeout)}));
}

TEST_F(NodeDeadline, PendingResetAndRefusedWorkAreDueNow) {
  io.node().request_reset(kResetCommunication);
  EXPECT_EQ(deadline(), h.now);
  h.advance_us(0);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_FALSE(pending());
}

TEST_F(NodeDeadline, AcrossTheClockWrap) {
  h.now = 0xFFFFFFFFu - 30000u;
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);
  const uint32_t at = deadline();
  EXPECT_EQ(at, h.now + 100000u);
  EXPECT_LT(at, 100000u) << "wrapped";
  EXPECT_EQ(run_to(at), Frames({"<703> 7F"}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
