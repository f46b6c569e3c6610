// The station image's CAN port (issue 23 item 1), its code built on the
// host: the gateway's acceptance ranges (its node's ids) reach the MCP2515
// filter planner through CanControl::set_filters, and the chip, once the
// plan is programmed, admits exactly what the plan computed from those
// ranges admits, every id the gateway needs among them; frames through the
// filters and the controller's events reach the gateway (CanInput). Black
// box on the chip model's bus side; the plan is the planner's own
// (mcp2515.FilterPlanner tests hold it to the reference search).
#include <gtest/gtest.h>

#include <set>
#include <type_traits>
#include <vector>

#include "filter_plan.h"
#include "uno_can_rig.h"

namespace mb2co {
namespace test {
namespace {

static_assert(!profile::kNetwork, "built with the station profile");
static_assert(std::is_same<UnoCanRig::Port, avr::CanPort<true>>::value,
              "the station's ranges are single ids: it plans filters");

using Ids = std::set<uint16_t>;

/// Long enough for any plan: a step per pass, at most a few hundred steps.
constexpr uint32_t kPlanUs = 400 * UnoCanRig::kPassUs;

/// Every standard id the chip lets through now, probed with one data frame
/// each and drained by the driver itself: the probes never reach the
/// gateway.
Ids chip_admits(UnoCanRig& uno) {
  Ids ids;
  for (uint16_t id = 0; id <= mcp2515::kMaxStandardId; ++id) {
    if (uno.chip.receive_from_bus(can_frame(id, {0xA5})) >= 0) ids.insert(id);
    uno.driver.service();
    CanFrame f;
    while (uno.driver.receive(f)) {
    }
  }
  return ids;
}

/// The gateway's ranges: single ids on the station, so the ids themselves.
Ids wanted(const gateway::Gateway& gw) {
  CanIdRange ranges[canopen::kMaxAcceptanceRanges];
  const uint8_t n = gw.acceptance(ranges);
  Ids ids;
  for (uint8_t i = 0; i < n; ++i) {
    EXPECT_EQ(ranges[i].mask, kCanRangeExact) << "a station range of one id";
    ids.insert(ranges[i].id);
  }
  return ids;
}

/// What the plan for `ids` admits.
Ids plan_admits(const Ids& ids, mcp2515::FilterPlan* plan) {
  const std::vector<uint16_t> list(ids.begin(), ids.end());
  EXPECT_TRUE(mcp2515::plan_filters(list.data(), static_cast<uint8_t>(list.size()), *plan));
  Ids admitted;
  for (uint16_t id = 0; id <= mcp2515::kMaxStandardId; ++id) {
    if (mcp2515::plan_accepts(*plan, id)) admitted.insert(id);
  }
  return admitted;
}

TEST(StationImagePort, TheGatewaysRangesReachThePlannerAndTheChip) {
  UnoCanRig uno;
  uno.gw.start(uno.now_us, 1);
  uno.pass();  // the node hands its ranges over, the planner takes a first step
  EXPECT_EQ(chip_admits(uno).size(), 2048u) << "open while the plan is computed";
  uno.run_us(kPlanUs);
  const Ids ids = wanted(uno.gw);
  EXPECT_EQ(ids.count(0x000), 1u) << "NMT";
  EXPECT_EQ(ids.count(0x601), 1u) << "its SDO requests";
  mcp2515::FilterPlan plan;
  const Ids expected = plan_admits(ids, &plan);
  const Ids admitted = chip_admits(uno);
  EXPECT_EQ(admitted, expected);
  EXPECT_EQ(admitted.size(), plan.accepted_ids);
  for (uint16_t id : ids) EXPECT_EQ(admitted.count(id), 1u) << std::hex << id << " is needed";
  EXPECT_LT(admitted.size(), 2048u / 4) << "filters, not an open chip";
}

TEST(StationImagePort, FewIdsAreAdmittedExactlyAndChangesArePlannedAgain) {
  UnoCanRig uno;
  uno.power_on(1);
  // Fewer than the chip's 6 filters: every RPDO off, no heartbeat watched
  // (until the next reset derives them again).
  canopen::ObjectDictionary& od = uno.gw.od();
  uint8_t off[4];
  for (uint8_t n = 0; n < canopen::kPdoCount; ++n) {
    canopen::put_le32(off, od.get(od.find(static_cast<uint16_t>(0x1400 + n), 1)) | 0x80000000u);
    ASSERT_EQ(od.write(static_cast<uint16_t>(0x1400 + n), 1, off, 4), canopen::kSdoOk);
  }
  canopen::put_le32(off, 0);
  for (uint8_t sub = 1; sub <= canopen::kHbConsumers; ++sub) {
    ASSERT_EQ(od.write(0x1016, sub, off, 4), canopen::kSdoOk);
  }
  uno.run_us(kPlanUs);
  const Ids ids = wanted(uno.gw);
  EXPECT_LE(ids.size(), 6u);
  EXPECT_EQ(chip_admits(uno), ids) << "exactly the gateway's ids";

  // A heartbeat to watch: the node hands the new set over, the port plans
  // it (open meanwhile), the chip admits it.
  canopen::put_le32(off, (0x20u << 16) | 1000u);
  ASSERT_EQ(od.write(0x1016, 1, off, 4), canopen::kSdoOk);
  uno.pass();
  EXPECT_EQ(chip_admits(uno).size(), 2048u) << "open while planning";
  uno.run_us(kPlanUs);
  Ids more = ids;
  more.insert(0x720);
  EXPECT_EQ(wanted(uno.gw), more);
  EXPECT_EQ(chip_admits(uno), more);
}

TEST(StationImagePort, FramesThroughTheFiltersReachTheGateway) {
  UnoCanRig uno;
  uno.power_on(1);
  uno.run_us(kPlanUs);
  ASSERT_EQ(uno.gw.node().nmt_state(), canopen::kNmtOperational) << "self-starting";
  EXPECT_LT(uno.chip.receive_from_bus(can_frame(0x123, {0x02, 0x01})), 0) << "not the gateway's: filtered";
  ASSERT_GE(uno.chip.receive_from_bus(can_frame(0x000, {0x02, 0x01})), 0);  // NMT stop node 1
  uno.pass();
  EXPECT_EQ(uno.gw.node().nmt_state(), canopen::kNmtStopped);
}

TEST(StationImagePort, ControllerEventsReachTheGatewaysNode) {
  UnoCanRig uno;
  uno.power_on(1);
  uno.run_us(kPlanUs);
  // NMT frames before the port looks, until the chip loses one (one or
  // two buffers hold them, as the plan puts 000h in RXB0 or RXB1).
  const CanFrame enter_preop = can_frame(0x000, {0x80, 0x01});
  int got = 0;
  for (int i = 0; i < 3 && got != -2; ++i) got = uno.chip.receive_from_bus(enter_preop);
  ASSERT_EQ(got, -2) << "overflow";
  EXPECT_FALSE(uno.gw.node().emcy().active(0x8110));
  uno.run_us(10 * UnoCanRig::kPassUs);
  EXPECT_TRUE(uno.gw.node().emcy().active(0x8110)) << "CAN overrun";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
