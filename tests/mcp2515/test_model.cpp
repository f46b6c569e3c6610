// The model itself: the datasheet rules the driver tests rely on.
#include <gtest/gtest.h>

#include "mcp2515_model.h"
#include "mcp2515_regs.h"
#include "test_helpers.h"

namespace mb2co::mcp2515::test {
namespace {

class ModelTest : public ::testing::Test {
 protected:
  uint8_t read(uint8_t address) {
    chip.select(true);
    chip.transfer(reg::kRead);
    chip.transfer(address);
    const uint8_t v = chip.transfer(0);
    chip.select(false);
    return v;
  }
  void write(uint8_t address, uint8_t value) {
    chip.select(true);
    chip.transfer(reg::kWrite);
    chip.transfer(address);
    chip.transfer(value);
    chip.select(false);
  }
  void bit_modify(uint8_t address, uint8_t mask, uint8_t value) {
    chip.select(true);
    for (uint8_t b : {reg::kBitModify, address, mask, value}) chip.transfer(b);
    chip.select(false);
  }
  Mcp2515Model chip;
};

TEST_F(ModelTest, ResetStateIsConfigurationModeWithCanstatMirrored) {
  EXPECT_EQ(read(reg::kCanStat) & reg::kModeMask, reg::kModeConfig);
  for (uint8_t row = 0; row < 8; ++row) {
    EXPECT_EQ(read(static_cast<uint8_t>(row * 16 + 0x0E)), read(reg::kCanStat));
    EXPECT_EQ(read(static_cast<uint8_t>(row * 16 + 0x0F)), 0x87);
  }
}

TEST_F(ModelTest, FiltersMasksAndBitTimingAreWritableOnlyInConfigurationMode) {
  write(reg::kCnf1, 0x03);
  write(reg::kRxM0Sidh, 0xAB);
  EXPECT_EQ(read(reg::kCnf1), 0x03);
  EXPECT_EQ(read(reg::kRxM0Sidh), 0xAB);
  write(reg::kCanCtrl, reg::kModeNormal);
  write(reg::kCnf1, 0x01);
  write(reg::kRxM0Sidh, 0x11);
  write(reg::rxf_sidh(4), 0x22);
  EXPECT_EQ(read(reg::kCnf1), 0x03);
  EXPECT_EQ(read(reg::kRxM0Sidh), 0xAB);
  EXPECT_EQ(read(reg::rxf_sidh(4)), 0x00);
}

TEST_F(ModelTest, BitModifyActsAsWriteOnRegistersWithoutIt) {
  bit_modify(reg::kCanIntE, 0x01, 0xFF);  // bit-modifiable: only bit 0 changes
  EXPECT_EQ(read(reg::kCanIntE), 0x01);
  bit_modify(reg::kRxM1Sidh, 0x01, 0xF0);  // not bit-modifiable: mask forced to FFh
  EXPECT_EQ(read(reg::kRxM1Sidh), 0xF0);
}

TEST_F(ModelTest, TransmitBufferIsLockedWhileItsRequestIsPending) {
  write(reg::kCanCtrl, reg::kModeNormal);
  write(reg::tx_ctrl(1) + reg::kOffSidh, 0x12);
  chip.select(true);
  chip.transfer(reg::kRts | 0x02);
  chip.select(false);
  write(reg::tx_ctrl(1) + reg::kOffSidh, 0x34);
  EXPECT_EQ(read(reg::tx_ctrl(1) + reg::kOffSidh), 0x12);
  EXPECT_EQ(chip.transmit(), 1);
  ASSERT_EQ(chip.bus.size(), 1u);
  EXPECT_EQ(chip.bus[0].id, 0x12u << 3);
  EXPECT_TRUE(read(reg::kCanIntF) & reg::kIntTx1);
}

TEST_F(ModelTest, StandardFiltersCompareDataBytesThroughTheEidMaskBits) {
  // Mask: all SID bits and all of data byte 0; filter 0x123 with data[0] = 0x55.
  for (uint8_t a : {reg::kRxM0Sidh, reg::kRxM1Sidh}) {
    write(a, 0xFF);
    write(a + 1, 0xE0);
    write(a + 2, 0xFF);
  }
  for (uint8_t f = 0; f < 6; ++f) {
    write(reg::rxf_sidh(f), 0x123 >> 3);
    write(reg::rxf_sidh(f) + 1, (0x123 & 7) << 5);
    write(reg::rxf_sidh(f) + 2, 0x55);
  }
  write(reg::kCanCtrl, reg::kModeNormal);
  EXPECT_EQ(chip.receive_from_bus(frame(0x123, {0x54})), -1);
  EXPECT_EQ(chip.receive_from_bus(frame(0x124, {0x55})), -1);
  EXPECT_EQ(chip.receive_from_bus(frame(0x123, {0x55, 0x99})), 0);
}

TEST_F(ModelTest, AbsentChipAnswersAConstant) {
  chip.set_absent(true, 0x00);
  EXPECT_EQ(read(reg::kCanStat), 0x00);
  write(reg::kCnf1, 0x03);
  chip.set_absent(false);
  EXPECT_EQ(read(reg::kCnf1), 0x00);
}

}  // namespace
}  // namespace mb2co::mcp2515::test
