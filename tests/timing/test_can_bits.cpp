// Frame lengths: the numbers of seed 000 §2.10, both worst-case conventions,
// and exact stuffing checked against an independent bit-string model.
#include <gtest/gtest.h>

#include <random>
#include <string>

#include "timing/can_bits.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

TEST(CanBits, SeedMinimumAndMaximumWithoutStuffing) {
  EXPECT_EQ(frame_bits_unstuffed(false, 0), 47);   // §2.10: minimum 47 bits
  EXPECT_EQ(frame_bits_unstuffed(false, 8), 111);  // 47 + 64
}

TEST(CanBits, SeedWorstCaseIs130BitsFor8Bytes) {
  EXPECT_EQ(stuffable_bits(false, 8) + 1, 99);  // the seed counts the CRC as 16 bits
  EXPECT_EQ(worst_stuff_bits(false, 8, WorstCase::kCourse), 19);
  EXPECT_EQ(frame_bits_worst(false, 8, WorstCase::kCourse), 130);
}

TEST(CanBits, SeedTransmissionTimes) {
  EXPECT_EQ(bits_to_ns_ceil(130, 50000), 2600000u);   // 2.6 ms at 50 kbit/s
  EXPECT_EQ(bits_to_ns_ceil(130, 1000000), 130000u);  // 130 µs at 1 Mbit/s
}

TEST(CanBits, DavisBoundIs55Plus10nAnd80Plus10n) {
  for (uint8_t n = 0; n <= 8; ++n) {
    EXPECT_EQ(frame_bits_worst(false, n, WorstCase::kDavis), 55 + 10 * n) << int{n};
    EXPECT_EQ(frame_bits_worst(true, n, WorstCase::kDavis), 80 + 10 * n) << int{n};
  }
}

TEST(CanBits, CourseConventionForExtendedIdentifiers) {
  // 67 + 8n unstuffed, floor((55 + 8n)/5) stuff bits.
  EXPECT_EQ(frame_bits_unstuffed(true, 0), 67);
  EXPECT_EQ(frame_bits_worst(true, 0, WorstCase::kCourse), 67 + 11);
  EXPECT_EQ(frame_bits_worst(true, 8, WorstCase::kCourse), 131 + 23);
}

TEST(CanBits, DlcAbove8MeansEightBytes) {
  EXPECT_EQ(frame_bits_unstuffed(false, 15), frame_bits_unstuffed(false, 8));
}

TEST(CanBits, Crc15CheckValue) {
  // CRC-15/CAN of "123456789" is 0x059E (the published check value).
  uint16_t crc = 0;
  for (const char c : std::string("123456789")) {
    for (int b = 7; b >= 0; --b) crc = crc15_update(crc, ((c >> b) & 1) != 0);
  }
  EXPECT_EQ(crc, 0x059E);
}

TEST(CanBits, AllZeroFrameByHand) {
  // SOF..DLC are 19 dominant bits, the CRC of zeros is zero: 34 zeros get a
  // stuff bit after every 5 (the stuff bit starts the next run): 6 stuff bits.
  CanFrame f{};
  const ExactFrameBits e = frame_bits_exact(f);
  EXPECT_EQ(e.crc15, 0);
  EXPECT_EQ(e.stuff_bits, 6);
  EXPECT_EQ(e.total_bits, 47 + 6);
}

// --- an independent model: the frame as a string of '0'/'1', the CRC by
// polynomial division, stuffing by rewriting the string.
std::string bits_of(uint32_t v, int width) {
  std::string s;
  for (int i = width - 1; i >= 0; --i) s += ((v >> i) & 1u) ? '1' : '0';
  return s;
}

std::string crc_by_division(const std::string& message) {
  const std::string poly = "1100010110011001";  // x^15+x^14+x^10+x^8+x^7+x^4+x^3+1
  std::string r = message + std::string(15, '0');
  for (size_t i = 0; i + 15 < r.size(); ++i) {
    if (r[i] == '1') {
      for (size_t k = 0; k < poly.size(); ++k) r[i + k] = r[i + k] == poly[k] ? '0' : '1';
    }
  }
  return r.substr(r.size() - 15);
}

std::string stuffed(const std::string& in) {
  std::string out;
  for (const char b : in) {
    out += b;
    if (out.size() >= 5 && out.compare(out.size() - 5, 5, std::string(5, b)) == 0) {
      out += b == '0' ? '1' : '0';
    }
  }
  return out;
}

int model_total_bits(const CanFrame& f) {
  std::string s = "0";
  if (f.extended()) {
    s += bits_of(f.id >> 18, 11) + "11" + bits_of(f.id & 0x3FFFF, 18) + (f.rtr() ? "1" : "0") + "00";
  } else {
    s += bits_of(f.id, 11) + (f.rtr() ? "1" : "0") + "00";
  }
  s += bits_of(f.dlc, 4);
  if (!f.rtr()) {
    for (int i = 0; i < f.dlc; ++i) s += bits_of(f.data[i], 8);
  }
  s += crc_by_division(s);
  return static_cast<int>(stuffed(s).size()) + 13;
}

TEST(CanBits, ExactStuffingMatchesIndependentModel) {
  std::mt19937 rng(7);
  for (int n = 0; n < 3000; ++n) {
    CanFrame f{};
    const bool ext = (n & 1) != 0;
    f.flags = static_cast<uint8_t>((ext ? CanFrame::kExtended : 0) | (n % 7 == 0 ? CanFrame::kRtr : 0));
    f.id = static_cast<uint32_t>(rng()) & (ext ? 0x1FFFFFFFu : 0x7FFu);
    f.dlc = static_cast<uint8_t>(rng() % 9);
    // Sparse bytes give long runs, dense ones few: mix both.
    for (auto& b : f.data)
      b = (n % 3 == 0) ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(rng() % 2 ? 0 : 0xFF);
    ASSERT_EQ(frame_bits_exact(f).total_bits, model_total_bits(f)) << n;
  }
}

// Data bits that always repeat the bus level of the current run (stuff bits
// included) draw a stuff bit every 4 bits: the pattern the course bound
// misses. Built here from the stuffing rule for a given identifier.
CanFrame greedy_worst_frame(uint32_t id) {
  CanFrame f{};
  f.id = id;
  f.dlc = 8;
  char last = 'x';
  int run = 0;
  auto push = [&](char b) {
    run = b == last ? run + 1 : 1;
    last = b;
    if (run == 5) {
      last = b == '0' ? '1' : '0';
      run = 1;
    }
  };
  for (const char b : "0" + bits_of(id, 11) + "000" + bits_of(8, 4)) push(b);
  for (int byte = 0; byte < 8; ++byte) {
    for (int bit = 7; bit >= 0; --bit) {
      const char b = last;
      if (b == '1') f.data[byte] = static_cast<uint8_t>(f.data[byte] | (1u << bit));
      push(b);
    }
  }
  return f;
}

TEST(CanBits, ExactNeverExceedsDavisBoundButCanExceedTheCourseBound) {
  int longest = 0;
  for (uint32_t id = 0; id <= 0x7FF; ++id) {
    const CanFrame f = greedy_worst_frame(id);
    const int bits = frame_bits_exact(f).total_bits;
    ASSERT_EQ(bits, model_total_bits(f));
    ASSERT_LE(bits, frame_bits_worst(false, 8, WorstCase::kDavis));
    if (bits > longest) longest = bits;
  }
  EXPECT_GT(longest, frame_bits_worst(false, 8, WorstCase::kCourse));
}

TEST(CanBits, DocumentedFrameBeyondTheCourseBound) {
  // docs/timing.md: `mb2co-timing frame --id 0x03E --data 3C3C3C3C3C3C3C1B`.
  CanFrame f{};
  f.id = 0x03E;
  f.dlc = 8;
  const uint8_t data[8] = {0x3C, 0x3C, 0x3C, 0x3C, 0x3C, 0x3C, 0x3C, 0x1B};
  for (int i = 0; i < 8; ++i) f.data[i] = data[i];
  const ExactFrameBits e = frame_bits_exact(f);
  EXPECT_EQ(e.total_bits, model_total_bits(f));
  EXPECT_EQ(e.total_bits, 132);
  EXPECT_EQ(e.stuff_bits, 21);  // more than the 19 of the seed's bound
}

TEST(CanBits, RemoteFrameHasNoDataField) {
  CanFrame f{};
  f.id = 0x123;
  f.dlc = 8;
  f.flags = CanFrame::kRtr;
  const ExactFrameBits e = frame_bits_exact(f);
  EXPECT_EQ(e.total_bits - e.stuff_bits, frame_bits_unstuffed(false, 0));
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
