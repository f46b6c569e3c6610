// What the node asks of its CAN port (shared/platform/device_port.h): the ids it
// consumes (Node::consumed_ids, handed to CanControl::set_filters at reset
// and after a write that changes them) and the EMCY policy for controller
// events (Node::on_controller_state). Black box: SDO writes in, calls and
// frames out.
#include <gtest/gtest.h>

#include <vector>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Ids = std::vector<uint16_t>;

/// Every set_filters call the node made, in order.
std::vector<Ids> g_filter_calls;

void record_filters(void*, const uint16_t* ids, uint8_t count) {
  g_filter_calls.emplace_back(ids, ids + count);
}

const CanControl kRecordingControl = {nullptr, &record_filters};

class ConsumedIds : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 3;
  void SetUp() override {
    g_filter_calls.clear();
    io.node().set_can_control(&kRecordingControl);
    io.start(kId, h.now);
    bus.frames.clear();
  }
  Ids consumed() {
    uint16_t ids[kMaxConsumedIds];
    const uint8_t n = io.node().consumed_ids(ids);
    return Ids(ids, ids + n);
  }

  FrameLog bus;
  ionode::IoNode io{bus.sink()};
  Harness h{io.node(), bus};
};

TEST_F(ConsumedIds, DefaultsAreNmtSyncRpdoSdoAndGuarding) {
  const Ids expected = {0x000, 0x080, 0x203, 0x603, 0x703};
  EXPECT_EQ(consumed(), expected);
  ASSERT_EQ(g_filter_calls.size(), 1u) << "one call at the power-on reset";
  EXPECT_EQ(g_filter_calls[0], expected);
}

TEST_F(ConsumedIds, FollowSdoWritesAtTheNextProcess) {
  ASSERT_EQ(h.write_u32(0x1016, 1, (5u << 16) | 100u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x081), 0u);
  ASSERT_EQ(h.write_u32(0x1400, 1, 0x80000000u | 0x203u), 0u);  // RPDO1 invalid
  const Ids expected = {0x000, 0x081, 0x603, 0x703, 0x705};
  EXPECT_EQ(consumed(), expected);
  ASSERT_FALSE(g_filter_calls.empty());
  EXPECT_EQ(g_filter_calls.back(), expected) << "the port got the new set";
}

TEST_F(ConsumedIds, HeartbeatConsumersNeedANodeIdAndATime) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 100u), 0u);                // node 0
  ASSERT_EQ(h.write_u32(0x1016, 2, 7u << 16), 0u);            // no time
  ASSERT_EQ(h.write_u32(0x1016, 3, (kId << 16) | 100u), 0u);  // 703h: consumed once
  ASSERT_EQ(h.write_u32(0x1016, 4, (127u << 16) | 100u), 0u);
  EXPECT_EQ(consumed(), Ids({0x000, 0x080, 0x203, 0x603, 0x703, 0x77F}));
}

TEST_F(ConsumedIds, ResetCommunicationSetsTheFiltersAgain) {
  ASSERT_EQ(h.write_u32(0x1016, 1, (9u << 16) | 100u), 0u);
  h.advance_us(10);
  g_filter_calls.clear();
  h.nmt(0x82, kId);  // reset communication: 1016h back to its default
  ASSERT_EQ(g_filter_calls.size(), 1u);
  EXPECT_EQ(g_filter_calls[0], Ids({0x000, 0x080, 0x203, 0x603, 0x703}));
}

using ControllerState = IoNodeTest;

TEST_F(ControllerState, OverrunAndBusOffRecoveryHoldTheirEmcyForOneSecond) {
  EmcyProducer& e = io.node().emcy();
  io.node().on_controller_state(kControllerRxOverflow, false, h.now);
  io.node().on_controller_state(kControllerBusOffRecovered, false, h.now + 1000);
  EXPECT_TRUE(e.active(0x8110));
  EXPECT_TRUE(e.active(0x8140));
  h.advance_us(Node::kControllerEventHoldUs - 1);
  EXPECT_TRUE(e.active(0x8110));
  h.advance_us(1);
  EXPECT_FALSE(e.active(0x8110));
  EXPECT_TRUE(e.active(0x8140)) << "held from its own event";
  h.advance_us(1000);
  EXPECT_FALSE(e.active(0x8140));
  EXPECT_EQ(h.read(0x1003, 1), 0x8140u);
  EXPECT_EQ(h.read(0x1003, 2), 0x8110u);
}

TEST_F(ControllerState, ErrorPassiveWhileTheControllerIsPassive) {
  EmcyProducer& e = io.node().emcy();
  io.node().on_controller_state(kControllerStateChanged, true, h.now);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({"<083> 20 81 11 00 00 00 00 00"}));
  h.advance_us(5 * Node::kControllerEventHoldUs);
  EXPECT_TRUE(e.active(0x8120)) << "no timeout: as long as the state lasts";
  io.node().on_controller_state(kControllerStateChanged, false, h.now);
  EXPECT_FALSE(e.active(0x8120));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
