// receive()/service(): frames out in arrival order, hardware filters accept
// exactly what they should, overflow counted and cleared, RTR and extended.
#include <gtest/gtest.h>

#include <set>
#include <vector>

#include "mcp2515_regs.h"
#include "test_helpers.h"

namespace mb2co::mcp2515::test {
namespace {

using RxTest = DriverTest;

TEST_F(RxTest, ReceivedFrameComesOutAfterServiceAndInterruptClears) {
  CanFrame f;
  EXPECT_FALSE(driver.receive(f));
  const CanFrame sent = frame(0x181, {0xDE, 0xAD, 0xBE, 0xEF});
  ASSERT_EQ(chip.receive_from_bus(sent), 0);
  EXPECT_TRUE(chip.int_low());
  EXPECT_FALSE(driver.receive(f)) << "receive() reads no chip; service() fetches";
  EXPECT_EQ(driver.service(), 0);
  EXPECT_FALSE(chip.int_low());
  ASSERT_TRUE(driver.receive(f));
  EXPECT_EQ(f, sent);
  EXPECT_FALSE(driver.receive(f));
  EXPECT_EQ(driver.counters().rx_frames, 1);
}

TEST_F(RxTest, RolloverKeepsArrivalOrder) {
  const CanFrame a = frame(0x201, {1}), b = frame(0x201, {2}), c = frame(0x201, {3});
  ASSERT_EQ(chip.receive_from_bus(a), 0);
  ASSERT_EQ(chip.receive_from_bus(b), 1) << "RXB0 full: rolls over into RXB1";
  driver.service();
  CanFrame f;
  ASSERT_TRUE(driver.receive(f));
  EXPECT_EQ(f, a);
  // service() emptied both buffers: c lands in RXB0 yet must come after b,
  // which is still waiting in the driver's stage.
  ASSERT_EQ(chip.receive_from_bus(c), 0);
  EXPECT_EQ(service_if_int(), 0);
  std::vector<CanFrame> rest;
  while (driver.receive(f)) rest.push_back(f);
  for (const CanFrame& g : drain()) rest.push_back(g);
  EXPECT_EQ(rest, (std::vector<CanFrame>{b, c}));
}

TEST_F(RxTest, ManyFramesInBurstsOfTwoArriveInOrder) {
  std::vector<CanFrame> sent, got;
  for (uint8_t i = 0; i < 100; ++i) {
    sent.push_back(frame(0x300u + i % 5u, {i}));
    ASSERT_GE(chip.receive_from_bus(sent.back()), 0);
    if (i % 2 == 1) {
      for (const CanFrame& f : drain()) got.push_back(f);
    }
  }
  EXPECT_EQ(got, sent);
  EXPECT_EQ(driver.counters().rx_frames, 100);
}

TEST_F(RxTest, RemoteAndExtendedFramesAreDecoded) {
  const CanFrame frames[] = {remote(0x701, 1),
                             remote(0x000, 0),
                             frame(0x1FFFFFFF, {1, 2, 3}, CanFrame::kExtended),
                             frame(0x00000000, {}, CanFrame::kExtended),
                             remote(0x1ABCDE12, 8, CanFrame::kExtended),
                             frame(0x7FF, {0xFF, 0, 0xFF, 0, 0xFF, 0, 0xFF, 0})};
  for (const CanFrame& f : frames) {
    ASSERT_EQ(chip.receive_from_bus(f), 0);
    const auto got = drain();
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0], f);
  }
}

TEST_F(RxTest, LoopbackReceivesOwnFramesAndNothingReachesTheBus) {
  ASSERT_TRUE(driver.set_mode(Mode::kLoopback));
  const CanFrame a = frame(0x123, {7}), b = remote(0x1FF34567, 2, CanFrame::kExtended);
  ASSERT_TRUE(driver.send(a));
  ASSERT_TRUE(driver.send(b));
  EXPECT_EQ(chip.transmit(), 2);
  EXPECT_TRUE(chip.bus.empty());
  EXPECT_EQ(drain(), (std::vector<CanFrame>{a, b}));
  EXPECT_EQ(chip.receive_from_bus(frame(0x100)), -1) << "loopback ignores the bus";
}

TEST_F(RxTest, OverflowIsCountedClearedAndReported) {
  ASSERT_EQ(chip.receive_from_bus(frame(0x100, {1})), 0);
  ASSERT_EQ(chip.receive_from_bus(frame(0x100, {2})), 1);
  ASSERT_EQ(chip.receive_from_bus(frame(0x100, {3})), -2);
  EXPECT_TRUE(chip.reg(reg::kEflg) & reg::kEflgRx1Ovr);
  const uint8_t events = driver.service();
  EXPECT_TRUE(events & kEventRxOverflow);
  EXPECT_EQ(driver.counters().rx_overflows, 1);
  EXPECT_EQ(chip.reg(reg::kEflg) & (reg::kEflgRx0Ovr | reg::kEflgRx1Ovr), 0);
  EXPECT_EQ(chip.reg(reg::kCanIntF) & reg::kIntErr, 0);
  EXPECT_FALSE(chip.int_low());
  CanFrame f;
  ASSERT_TRUE(driver.receive(f));
  EXPECT_EQ(f.data[0], 1);
  ASSERT_TRUE(driver.receive(f));
  EXPECT_EQ(f.data[0], 2);
  // Reported once; the next overflow counts again.
  EXPECT_EQ(driver.service() & kEventRxOverflow, 0);
  for (uint8_t i = 0; i < 4; ++i) chip.receive_from_bus(frame(0x100, {i}));
  EXPECT_TRUE(driver.service() & kEventRxOverflow);
  EXPECT_EQ(driver.counters().rx_overflows, 2);
  EXPECT_EQ(driver.error_state(), ErrorState::kActive);
}

// --- acceptance filters -----------------------------------------------------------

/// The standard ids the chip hands to the driver, tried one at a time.
std::set<uint32_t> ids_through(Mcp2515Model& chip, Driver& driver) {
  std::set<uint32_t> out;
  for (uint32_t id = 0; id <= 0x7FF; ++id) {
    if (chip.receive_from_bus(frame(id, {0xA5, 0x5A})) < 0) continue;
    driver.service();
    CanFrame f;
    while (driver.receive(f)) out.insert(f.id);
  }
  return out;
}

TEST_F(RxTest, ExactFiltersPassOnlyTheSubscribedIds) {
  const uint16_t ids[] = {0x000, 0x080, 0x183, 0x603, 0x702, 0x704};
  FilterPlan plan{};
  ASSERT_TRUE(driver.set_filters(ids, 6, &plan));
  EXPECT_TRUE(plan.exact);
  EXPECT_EQ(chip.mode(), reg::kModeNormal) << "mode restored after configuration";
  EXPECT_EQ(ids_through(chip, driver), (std::set<uint32_t>{0x000, 0x080, 0x183, 0x603, 0x702, 0x704}));
  EXPECT_EQ(chip.receive_from_bus(frame(0x183, {}, CanFrame::kExtended)), -1) << "extended frames filtered";
  EXPECT_GE(chip.receive_from_bus(remote(0x603, 0)), 0) << "remote frames of a subscribed id pass";
}

TEST_F(RxTest, WidenedFiltersPassEverySubscribedIdAndWhatThePlanSays) {
  const uint16_t ids[] = {0x000, 0x080, 0x082, 0x182, 0x184, 0x282, 0x603, 0x702, 0x704};
  FilterPlan plan{};
  ASSERT_TRUE(driver.set_filters(ids, 9, &plan));
  EXPECT_FALSE(plan.exact);
  const auto through = ids_through(chip, driver);
  for (uint16_t id : ids) EXPECT_TRUE(through.count(id)) << std::hex << id;
  EXPECT_EQ(through.size(), plan.accepted_ids);
  for (uint32_t id : through) EXPECT_TRUE(plan_accepts(plan, static_cast<uint16_t>(id)));
}

TEST_F(RxTest, SubscribedIdsOfRxB0RollOverAndRxB1IdsOverflowAlone) {
  // Three ids cannot share RXB0's two filters exactly: NMT and SYNC (the two
  // lowest) take RXB0, 0x700 goes to RXB1.
  const uint16_t ids[] = {0x700, 0x000, 0x080};
  FilterPlan plan{};
  ASSERT_TRUE(driver.set_filters(ids, 3, &plan));
  EXPECT_TRUE(plan.exact);
  EXPECT_EQ(chip.receive_from_bus(frame(0x700)), 1);
  EXPECT_EQ(chip.receive_from_bus(frame(0x700)), -2);
  EXPECT_TRUE(driver.service() & kEventRxOverflow);
  drain();
  EXPECT_EQ(chip.receive_from_bus(frame(0x000)), 0);
  EXPECT_EQ(chip.receive_from_bus(frame(0x080)), 1) << "rolled over";
}

TEST_F(RxTest, IdsThatFitRxB0AllGetTwoBuffersOfDepth) {
  const uint16_t ids[] = {0x080, 0x081, 0x700, 0x701};  // mask 0x7FE: two filters suffice
  FilterPlan plan{};
  ASSERT_TRUE(driver.set_filters(ids, 4, &plan));
  EXPECT_TRUE(plan.exact);
  EXPECT_EQ(chip.receive_from_bus(frame(0x700)), 0);
  EXPECT_EQ(chip.receive_from_bus(frame(0x700)), 1);
  EXPECT_EQ(drain().size(), 2u);
}

TEST_F(RxTest, AcceptAllAfterFiltersPassesEverything) {
  const uint16_t ids[] = {0x100};
  ASSERT_TRUE(driver.set_filters(ids, 1));
  EXPECT_EQ(chip.receive_from_bus(frame(0x101)), -1);
  ASSERT_TRUE(driver.accept_all());
  EXPECT_EQ(chip.receive_from_bus(frame(0x101)), 0);
  EXPECT_EQ(chip.receive_from_bus(frame(0x1234, {}, CanFrame::kExtended)), 1);
}

TEST_F(RxTest, BadFilterListChangesNothing) {
  const uint16_t bad[] = {0x100, 0x900};
  EXPECT_FALSE(driver.set_filters(bad, 2));
  EXPECT_FALSE(driver.set_filters(bad, 0));
  EXPECT_EQ(chip.receive_from_bus(frame(0x555)), 0) << "still accepting all";
}

}  // namespace
}  // namespace mb2co::mcp2515::test
