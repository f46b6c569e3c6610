// Error confinement: warning, error passive, bus-off counted and reported,
// recovery after 128 x 11 recessive bits noticed without an interrupt.
#include <gtest/gtest.h>

#include "mcp2515_regs.h"
#include "test_helpers.h"

namespace mb2co::mcp2515::test {
namespace {

using ErrorTest = DriverTest;

TEST_F(ErrorTest, CountersAreReadable) {
  chip.transmit_errors(3);
  chip.receive_errors(5);
  EXPECT_EQ(driver.tec(), 24);
  EXPECT_EQ(driver.rec(), 5);
}

TEST_F(ErrorTest, WarningAndPassiveAreReportedAsStateChanges) {
  chip.transmit_errors(12);  // TEC 96
  ASSERT_TRUE(chip.int_low());
  EXPECT_EQ(driver.service(), kEventStateChanged);
  EXPECT_EQ(driver.error_state(), ErrorState::kWarning);
  chip.transmit_errors(4);  // TEC 128
  EXPECT_EQ(service_if_int(), kEventStateChanged);
  EXPECT_EQ(driver.error_state(), ErrorState::kPassive);
  EXPECT_EQ(driver.service(), 0) << "no repeated report";
  // Successful frames bring TEC down; leaving passive raises no interrupt.
  ASSERT_TRUE(driver.send(frame(0x100)));
  chip.transmit();
  EXPECT_EQ(driver.tec(), 127);
  EXPECT_EQ(driver.service(), kEventStateChanged);
  EXPECT_EQ(driver.error_state(), ErrorState::kWarning);
}

TEST_F(ErrorTest, BusOffIsCountedAndRecoveryReported) {
  ASSERT_TRUE(driver.send(frame(0x181, {1})));
  chip.transmit_errors(32);  // TEC past 255
  ASSERT_TRUE(chip.int_low());
  const uint8_t events = driver.service();
  EXPECT_TRUE(events & kEventBusOff);
  EXPECT_TRUE(events & kEventStateChanged);
  EXPECT_EQ(driver.error_state(), ErrorState::kBusOff);
  EXPECT_EQ(driver.counters().bus_offs, 1);
  EXPECT_EQ(chip.transmit(), 0) << "a bus-off node sends nothing";

  chip.idle_bits(128 * 11 - 1);
  EXPECT_EQ(driver.service(), 0);
  EXPECT_EQ(driver.error_state(), ErrorState::kBusOff);
  chip.idle_bits(1);
  EXPECT_FALSE(chip.int_low()) << "the chip raises no interrupt on recovery";
  const uint8_t recovered = driver.service();  // the periodic call notices
  EXPECT_TRUE(recovered & kEventBusOffRecovered);
  EXPECT_FALSE(recovered & kEventBusOff);
  EXPECT_EQ(driver.error_state(), ErrorState::kActive);
  EXPECT_EQ(driver.tec(), 0);

  // The frame queued before bus-off goes out now; a second bus-off counts again.
  EXPECT_EQ(chip.transmit(), 1);
  EXPECT_EQ(chip.bus.at(0), frame(0x181, {1}));
  chip.transmit_errors(32);
  EXPECT_TRUE(driver.service() & kEventBusOff);
  EXPECT_EQ(driver.counters().bus_offs, 2);
}

TEST_F(ErrorTest, ReceiveWorksWhileErrorPassive) {
  chip.receive_errors(128);
  EXPECT_EQ(driver.service(), kEventStateChanged);
  EXPECT_EQ(driver.error_state(), ErrorState::kPassive);
  ASSERT_EQ(chip.receive_from_bus(frame(0x222, {5})), 0);
  EXPECT_EQ(drain(), (std::vector<CanFrame>{frame(0x222, {5})}));
}

}  // namespace
}  // namespace mb2co::mcp2515::test
