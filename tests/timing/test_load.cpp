// Bus load and bandwidth (seed 000 §2.11) and the exact utilisation bounds.
#include <gtest/gtest.h>

#include <vector>

#include "timing/message_set.h"
#include "timing/utilisation.h"

namespace mb2co {
namespace timing {
namespace {

MessageSpec message(uint32_t id, uint8_t dlc, uint32_t period_us, uint16_t bits = 0) {
  MessageSpec m{};
  m.id = id;
  m.dlc = dlc;
  m.period_us = period_us;
  m.deadline_us = period_us;
  m.bits = bits;
  return m;
}

bool exactly(const Utilisation& u, uint64_t whole) {
  return u.lower().whole == whole && u.lower().frac == 0 && u.upper().whole == whole && u.upper().frac == 0;
}

TEST(Load, FiveNodeSyncExampleIs1347Bits) {
  // 5 nodes x 2 PDOs of 8 bytes plus SYNC, every 100 ms, course convention.
  // The seed states the SYNC as 47 bits (its unstuffed length) and takes the
  // PDOs at their worst case, 130 bits: 47 + 10 x 130.
  std::vector<MessageSpec> set = {message(0x80, 0, 100000, 47)};
  for (uint32_t node = 1; node <= 5; ++node) {
    set.push_back(message(0x180 + node, 8, 100000));
    set.push_back(message(0x280 + node, 8, 100000));
  }
  EXPECT_EQ(window_bits(set.data(), set.size(), 100000, 100000, WorstCase::kCourse), 1347u);
  EXPECT_EQ(window_capacity_bits(100000, 100000), 10000u);  // fits at 100 kbit/s
  EXPECT_EQ(window_capacity_bits(100000, 10000), 1000u);    // not at 10 kbit/s
  // With the SYNC stuffed by the same bound: 54 + 1300.
  set[0].bits = 0;
  EXPECT_EQ(window_bits(set.data(), set.size(), 100000, 100000, WorstCase::kCourse), 1354u);
}

std::vector<MessageSpec> four_pdo_set() {
  return {message(0x181, 8, 10000, 130), message(0x182, 8, 5000, 50), message(0x183, 8, 5000, 50),
          message(0x184, 8, 2500, 80)};
}

TEST(Load, FourPdoSetIs65kbit) {
  const auto set = four_pdo_set();
  EXPECT_TRUE(exactly(bus_load_bps(set.data(), set.size(), 100000, WorstCase::kDavis), 65000));
  // U = load / bit rate: at 65 kbit/s the bus is exactly full, just above it fits.
  EXPECT_TRUE(set_utilisation(set.data(), set.size(), 65000, WorstCase::kDavis).reaches_one());
  EXPECT_TRUE(set_utilisation(set.data(), set.size(), 65001, WorstCase::kDavis).below_one());
}

TEST(Load, WithSyncEvery2point5msIs85kbit) {
  auto set = four_pdo_set();
  set.push_back(message(0x80, 0, 2500, 50));  // "approximately 50 bits"
  EXPECT_TRUE(exactly(bus_load_bps(set.data(), set.size(), 100000, WorstCase::kDavis), 85000));
  EXPECT_TRUE(set_utilisation(set.data(), set.size(), 85000, WorstCase::kDavis).reaches_one());
  EXPECT_TRUE(set_utilisation(set.data(), set.size(), 100000, WorstCase::kDavis).below_one());
}

TEST(Load, TransmissionTimeOverride) {
  MessageSpec m = message(0x181, 8, 3500);
  m.c_ns = 1000000;
  EXPECT_EQ(transmission_ticks(m, 1000000, WorstCase::kDavis), 1000u * 1000000u);
  EXPECT_EQ(message_bits(m, 125000, WorstCase::kDavis), 125u);
  m.c_ns = 0;
  EXPECT_EQ(message_bits(m, 125000, WorstCase::kDavis), 135u);
  EXPECT_EQ(message_bits(m, 125000, WorstCase::kCourse), 130u);
}

TEST(Utilisation, InexactTermsBracketTheValue) {
  Utilisation u;
  u.add(1, 3);
  EXPECT_EQ(u.lower().whole, 0u);
  EXPECT_EQ(u.upper().frac - u.lower().frac, 1u);
  EXPECT_TRUE(u.below_one());
  u.add(2, 3);  // exactly 1: counted as reaching 1
  EXPECT_TRUE(u.reaches_one());
}

TEST(Utilisation, FractionQ64) {
  bool exact = false;
  EXPECT_EQ(fraction_q64(1, 2, &exact), uint64_t{1} << 63);
  EXPECT_TRUE(exact);
  EXPECT_EQ(fraction_q64(1, 3, &exact), 0x5555555555555555u);
  EXPECT_FALSE(exact);
  // Denominators above 2^63 need the carry of the long division.
  const uint64_t big = (uint64_t{1} << 63) + 1;
  EXPECT_EQ(fraction_q64(big - 1, big, &exact), ~uint64_t{0} - 1);
}

TEST(MessageSet, ArbitrationOrder) {
  EXPECT_LT(arbitration_key(0x100, false), arbitration_key(0x101, false));
  // Standard beats extended with the same 11 base bits, loses to a lower base.
  EXPECT_LT(arbitration_key(0x100, false), arbitration_key(0x100u << 18, true));
  EXPECT_LT(arbitration_key(0x0FFu << 18 | 0x3FFFF, true), arbitration_key(0x100, false));
  std::vector<MessageSpec> set = {message(0x701, 1, 1), message(0x80, 0, 1), message(0x181, 2, 1)};
  sort_by_priority(set.data(), set.size());
  EXPECT_EQ(set[0].id, 0x80u);
  EXPECT_EQ(set[2].id, 0x701u);
  size_t a = 0, b = 0;
  EXPECT_FALSE(find_duplicate_id(set.data(), set.size(), &a, &b));
  set[1].id = 0x80;
  EXPECT_TRUE(find_duplicate_id(set.data(), set.size(), &a, &b));
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
