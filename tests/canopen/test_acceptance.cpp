// What the node asks of its CAN port (shared/platform/device_port.h): the
// frames it must receive as acceptance ranges (Node::acceptance, handed to
// CanControl::set_filters at reset and after a write that changes them) and
// the EMCY policy for controller events (Node::on_controller_state). Black
// box: SDO writes in, calls and frames out.
#include <gtest/gtest.h>

#include <ostream>
#include <set>
#include <vector>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Ids = std::set<uint16_t>;

/// What a set of ranges asks for: the ids of its one-id ranges, and its
/// wider ranges as id/mask pairs.
struct Wanted {
  Ids ids;
  std::vector<std::pair<uint16_t, uint16_t>> wider;
  bool operator==(const Wanted& o) const { return ids == o.ids && wider == o.wider; }
};
std::ostream& operator<<(std::ostream& os, const Wanted& w) {
  os << std::hex << "ids {";
  for (uint16_t id : w.ids) os << ' ' << id;
  os << " } wider {";
  for (const auto& r : w.wider) os << ' ' << r.first << '/' << r.second;
  return os << " }" << std::dec;
}
Wanted wanted(const CanIdRange* ranges, uint8_t count) {
  Wanted w;
  for (uint8_t i = 0; i < count; ++i) {
    if (ranges[i].mask == kCanRangeExact) {
      w.ids.insert(ranges[i].id);
    } else {
      w.wider.emplace_back(ranges[i].id, ranges[i].mask);
    }
  }
  return w;
}
/// The node's own ranges besides its ids: every remote frame where its
/// TPDOs answer remote requests (host builds).
std::vector<std::pair<uint16_t, uint16_t>> remote_policy() {
  if (profile::kTpdoRtr) return {{kCanRangeRemote, kCanRangeRemote}};
  return {};
}

/// Every set_filters call the node made, in order.
std::vector<Wanted> g_filter_calls;

void record_filters(void*, const CanIdRange* ranges, uint8_t count) {
  EXPECT_LE(count, kMaxAcceptanceRanges);
  g_filter_calls.push_back(wanted(ranges, count));
}

const CanControl kRecordingControl = {nullptr, &record_filters};

class Acceptance : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 3;
  void SetUp() override {
    g_filter_calls.clear();
    io.node().set_can_control(&kRecordingControl);
    io.start(kId, h.now);
    bus.frames.clear();
  }
  Wanted acceptance() {
    CanIdRange ranges[kMaxAcceptanceRanges];
    return wanted(ranges, io.node().acceptance(ranges));
  }
  /// `ids`; never TIME's 100h by default: 1012h's default (100h) has the
  /// consumer bit clear (canopen.time: AcceptanceHasTheTimeIdWhileConsuming).
  Wanted node_ids(Ids ids) { return Wanted{std::move(ids), remote_policy()}; }

  FrameLog bus;
  ionode::IoNode io{bus.sink()};
  Harness h{io.node(), bus};
};

TEST_F(Acceptance, DefaultsAreNmtSyncRpdoSdoAndGuarding) {
  const Wanted expected = node_ids({0x000, 0x080, 0x203, 0x603, 0x703});
  EXPECT_EQ(acceptance(), expected);
  ASSERT_EQ(g_filter_calls.size(), 1u) << "one call at the power-on reset";
  EXPECT_EQ(g_filter_calls[0], expected);
}

TEST_F(Acceptance, FollowSdoWritesAtTheNextProcess) {
  ASSERT_EQ(h.write_u32(0x1016, 1, (5u << 16) | 100u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x081), 0u);
  ASSERT_EQ(h.write_u32(0x1400, 1, 0x80000000u | 0x203u), 0u);  // RPDO1 invalid
  const Wanted expected = node_ids({0x000, 0x081, 0x603, 0x703, 0x705});
  EXPECT_EQ(acceptance(), expected);
  ASSERT_FALSE(g_filter_calls.empty());
  EXPECT_EQ(g_filter_calls.back(), expected) << "the port got the new set";
}

TEST_F(Acceptance, HeartbeatConsumersNeedANodeIdAndATime) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 100u), 0u);                // node 0
  ASSERT_EQ(h.write_u32(0x1016, 2, 7u << 16), 0u);            // no time
  ASSERT_EQ(h.write_u32(0x1016, 3, (kId << 16) | 100u), 0u);  // 703h: the guarding id again
  ASSERT_EQ(h.write_u32(0x1016, 4, (127u << 16) | 100u), 0u);
  EXPECT_EQ(acceptance(), node_ids({0x000, 0x080, 0x203, 0x603, 0x703, 0x77F}));
}

TEST_F(Acceptance, ResetCommunicationSetsTheFiltersAgain) {
  ASSERT_EQ(h.write_u32(0x1016, 1, (9u << 16) | 100u), 0u);
  h.advance_us(10);
  g_filter_calls.clear();
  h.nmt(0x82, kId);  // reset communication: 1016h back to its default
  ASSERT_EQ(g_filter_calls.size(), 1u);
  EXPECT_EQ(g_filter_calls[0], node_ids({0x000, 0x080, 0x203, 0x603, 0x703}));
}

// A device's other services (the gateway's network service) add their
// ranges after the node's, as the device set them.
TEST_F(Acceptance, ServiceRangesFollowTheNodesOwn) {
  static const CanIdRange kServices[] = {{0x580, 0x780}, {0x700, 0x780}};
  io.node().set_service_ranges(kServices, 2);
  CanIdRange ranges[kMaxAcceptanceRanges];
  const uint8_t n = io.node().acceptance(ranges);
  ASSERT_GE(n, 2);
  EXPECT_EQ(ranges[n - 2].id, 0x580);
  EXPECT_EQ(ranges[n - 2].mask, 0x780);
  EXPECT_EQ(ranges[n - 1].id, 0x700);
  EXPECT_EQ(ranges[n - 1].mask, 0x780);
  Wanted expected = node_ids({0x000, 0x080, 0x203, 0x603, 0x703});
  expected.wider.emplace_back(0x580, 0x780);
  expected.wider.emplace_back(0x700, 0x780);
  EXPECT_EQ(wanted(ranges, n), expected);
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
