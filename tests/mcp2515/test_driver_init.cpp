// begin(): bit timing per rate (read back from the chip and decoded), modes,
// interrupt enables, and a missing chip.
#include <gtest/gtest.h>

#include "mcp2515_regs.h"
#include "test_helpers.h"

namespace mb2co::mcp2515::test {
namespace {

struct RateCase {
  Bitrate rate;
  uint32_t bps;
  uint8_t cnf1, cnf2, cnf3;  // from the datasheet formulas, worked by hand
};

class InitPerRate : public ::testing::TestWithParam<RateCase> {
 protected:
  Mcp2515Model chip;
  Driver driver{chip.spi()};
};

TEST_P(InitPerRate, ProgramsBitTimingWithTheSamplePointInRange) {
  const RateCase c = GetParam();
  ASSERT_TRUE(driver.begin(c.rate, Mode::kNormal));
  const uint8_t cnf1 = chip.reg(reg::kCnf1), cnf2 = chip.reg(reg::kCnf2), cnf3 = chip.reg(reg::kCnf3);
  EXPECT_EQ(cnf1, c.cnf1);
  EXPECT_EQ(cnf2, c.cnf2);
  EXPECT_EQ(cnf3, c.cnf3);

  // Decode as the chip does and check the CAN rules independently.
  const unsigned brp = cnf1 & 0x3F, sjw = (cnf1 >> 6) + 1u;
  const unsigned prop = (cnf2 & 7) + 1u, ps1 = ((cnf2 >> 3) & 7) + 1u, ps2 = (cnf3 & 7) + 1u;
  ASSERT_TRUE(cnf2 & 0x80) << "BTLMODE: PS2 must come from CNF3";
  const unsigned tq = 1 + prop + ps1 + ps2;
  EXPECT_EQ(16000000u / (2u * (brp + 1u) * tq), c.bps);
  EXPECT_EQ(16000000u % (2u * (brp + 1u) * tq), 0u);
  const double sample = double(1 + prop + ps1) / tq;
  EXPECT_GE(sample, 0.75);
  EXPECT_LE(sample, 0.875);
  EXPECT_GE(prop + ps1, ps2);
  EXPECT_GT(ps2, sjw);
  EXPECT_GE(ps2, 2u);
  EXPECT_EQ(bits_per_second(c.rate), c.bps);
}

INSTANTIATE_TEST_SUITE_P(Rates, InitPerRate,
                         ::testing::Values(RateCase{Bitrate::k125k, 125000, 0x03, 0xBC, 0x01},
                                           RateCase{Bitrate::k250k, 250000, 0x01, 0xBC, 0x01},
                                           RateCase{Bitrate::k500k, 500000, 0x00, 0xBC, 0x01},
                                           RateCase{Bitrate::k1000k, 1000000, 0x00, 0x8A, 0x01}));

TEST(Init, EntersTheRequestedModeWithRxAndErrorInterruptsAndRollover) {
  for (Mode mode : {Mode::kNormal, Mode::kLoopback, Mode::kListenOnly}) {
    Mcp2515Model chip;
    Driver driver(chip.spi());
    ASSERT_TRUE(driver.begin(Bitrate::k250k, mode));
    const uint8_t want = mode == Mode::kNormal     ? reg::kModeNormal
                         : mode == Mode::kLoopback ? reg::kModeLoopback
                                                   : reg::kModeListenOnly;
    EXPECT_EQ(chip.mode(), want);
    EXPECT_EQ(chip.reg(reg::kCanIntE), reg::kIntRx0 | reg::kIntRx1 | reg::kIntErr);
    EXPECT_TRUE(chip.reg(reg::kRxB0Ctrl) & reg::kRxCtrlBukt);
    EXPECT_EQ(chip.reg(reg::kCanCtrl) & reg::kCanCtrlClkEn, 0) << "CLKOUT left running";
    EXPECT_FALSE(chip.int_low());
    EXPECT_EQ(driver.error_state(), ErrorState::kActive);
  }
}

TEST(Init, WaitsForSlowModeChanges) {
  Mcp2515Model chip;
  chip.set_mode_delay(40);
  Driver driver(chip.spi());
  ASSERT_TRUE(driver.begin(Bitrate::k125k, Mode::kNormal));
  EXPECT_EQ(chip.mode(), reg::kModeNormal);
  EXPECT_TRUE(driver.set_mode(Mode::kLoopback));
  EXPECT_EQ(chip.mode(), reg::kModeLoopback);
}

TEST(Init, FailsWithoutAChip) {
  for (uint8_t miso : {uint8_t{0x00}, uint8_t{0xFF}, uint8_t{0x80}}) {
    Mcp2515Model chip;
    chip.set_absent(true, miso);
    Driver driver(chip.spi());
    EXPECT_FALSE(driver.begin(Bitrate::k500k, Mode::kNormal)) << int{miso};
  }
}

TEST(Init, ReinitialisingResetsTheChip) {
  Mcp2515Model chip;
  Driver driver(chip.spi());
  ASSERT_TRUE(driver.begin(Bitrate::k500k, Mode::kNormal));
  const uint16_t ids[] = {0x123};
  ASSERT_TRUE(driver.set_filters(ids, 1));
  ASSERT_TRUE(driver.begin(Bitrate::k125k, Mode::kNormal));
  EXPECT_EQ(chip.reg(reg::kCnf1), 0x03);
  EXPECT_EQ(chip.receive_from_bus(frame(0x456)), 0) << "filters from before begin() still active";
}

TEST(Init, EverySpiInstructionEndsWithChipSelectReleased) {
  Mcp2515Model chip;
  Driver driver(chip.spi());
  ASSERT_TRUE(driver.begin(Bitrate::k500k, Mode::kNormal));
  const int before = chip.spi_transactions();
  EXPECT_TRUE(driver.send(frame(0x100, {1})));
  EXPECT_GT(chip.spi_transactions(), before);
  // A transfer with CS released is not seen by the chip: MISO floats high.
  EXPECT_EQ(chip.transfer(reg::kReadStatus), 0xFF);
}

}  // namespace
}  // namespace mb2co::mcp2515::test
