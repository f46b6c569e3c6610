#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "crc/crc16.h"

namespace mb2co {
namespace modbus {
namespace {

// The bitwise definition of the serial line spec §6.2.2, independent of the table.
uint16_t crc_bitwise(const std::vector<uint8_t>& data) {
  uint16_t crc = 0xFFFF;
  for (uint8_t b : data) {
    crc ^= b;
    for (int i = 0; i < 8; ++i)
      crc = (crc & 1) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

TEST(ModbusCrc, SerialLineSpecExample) {
  // Serial line spec Appendix B: CRC of 02 07 is 0x1241, sent 41 12.
  uint8_t frame[4] = {0x02, 0x07};
  EXPECT_EQ(crc16(frame, 2), 0x1241);
  EXPECT_EQ(append_crc(frame, 2), 4);
  EXPECT_EQ(frame[2], 0x41);
  EXPECT_EQ(frame[3], 0x12);
  EXPECT_TRUE(crc_ok(frame, 4));
}

TEST(ModbusCrc, KnownFrames) {
  // Read holding registers 0x6B..0x6D of slave 0x11 (the classic example).
  const uint8_t read[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87};
  EXPECT_TRUE(crc_ok(read, sizeof read));
  const uint8_t read10[] = {0x01, 0x03, 0x00, 0x00, 0x00, 0x0A, 0xC5, 0xCD};
  EXPECT_TRUE(crc_ok(read10, sizeof read10));
  // CRC-16/MODBUS check value of the catalogue of CRC algorithms.
  const uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(crc16(check, sizeof check), 0x4B37);
}

TEST(ModbusCrc, TableMatchesBitwiseDefinition) {
  std::mt19937 rng(7);
  for (int round = 0; round < 200; ++round) {
    std::vector<uint8_t> data(rng() % 256);
    for (auto& b : data) b = static_cast<uint8_t>(rng());
    EXPECT_EQ(crc16(data.data(), static_cast<uint16_t>(data.size())), crc_bitwise(data));
  }
}

TEST(ModbusCrc, ChainsAcrossBuffers) {
  const uint8_t data[] = {1, 2, 3, 4, 5, 6, 7};
  EXPECT_EQ(crc16(data + 3, 4, crc16(data, 3)), crc16(data, 7));
}

TEST(ModbusCrc, RejectsCorruptionAndShortInput) {
  uint8_t frame[] = {0x11, 0x03, 0x00, 0x6B, 0x00, 0x03, 0x76, 0x87};
  for (size_t i = 0; i < sizeof frame; ++i) {
    frame[i] ^= 0x10;
    EXPECT_FALSE(crc_ok(frame, sizeof frame)) << "byte " << i;
    frame[i] ^= 0x10;
  }
  EXPECT_FALSE(crc_ok(frame, 2));
  EXPECT_FALSE(crc_ok(frame, 0));
}

// crc_ok() checks the residue (CRC over body and CRC is 0): it must accept
// exactly the frames whose last two bytes are the body's CRC, low byte first.
TEST(ModbusCrc, AcceptsExactlyTheRightCrcBytes) {
  std::mt19937 rng(11);
  for (int round = 0; round < 8; ++round) {
    std::vector<uint8_t> frame(1 + rng() % 20 + 2);
    for (auto& b : frame) b = static_cast<uint8_t>(rng());
    const uint16_t body = static_cast<uint16_t>(frame.size() - 2);
    const uint16_t crc = crc_bitwise(std::vector<uint8_t>(frame.begin(), frame.begin() + body));
    // Every possible pair of CRC bytes: only the right one passes.
    for (uint32_t candidate = 0; candidate <= 0xFFFF; ++candidate) {
      frame[body] = static_cast<uint8_t>(candidate);
      frame[body + 1u] = static_cast<uint8_t>(candidate >> 8);
      ASSERT_EQ(crc_ok(frame.data(), static_cast<uint16_t>(frame.size())), candidate == crc)
          << "round " << round << " candidate " << candidate;
    }
  }
}

}  // namespace
}  // namespace modbus
}  // namespace mb2co
