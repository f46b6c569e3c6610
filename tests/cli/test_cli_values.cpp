// The value parsers every program shares (shared/host/cli_values.h): what a
// user may type for a bit rate, a parity, a number or a duration, and the one
// line a wrong value gets.
#include <gtest/gtest.h>

#include "host/cli_values.h"

namespace {

using namespace mb2co;
using namespace mb2co::cli;

uint32_t bitrate_of(const std::string& text) {
  uint32_t bps = 0;
  const Status s = parse_bitrate("--bitrate", text, 1000, 1000000, &bps);
  EXPECT_TRUE(s.is_ok()) << text << ": " << s.message();
  return bps;
}

std::string bitrate_error(const std::string& text) {
  uint32_t bps = 12345;
  const Status s = parse_bitrate("--bitrate", text, 1000, 1000000, &bps);
  EXPECT_FALSE(s.is_ok()) << text;
  EXPECT_EQ(bps, 12345u) << "untouched on failure";
  return s.message();
}

TEST(Bitrate, SuffixesAndBitPerSecondMeanTheSame) {
  EXPECT_EQ(bitrate_of("500k"), 500000u);
  EXPECT_EQ(bitrate_of("500K"), 500000u);
  EXPECT_EQ(bitrate_of("500000"), 500000u);
  EXPECT_EQ(bitrate_of("1M"), 1000000u);
  EXPECT_EQ(bitrate_of("1000k"), 1000000u);
  EXPECT_EQ(bitrate_of("125000"), 125000u);
  EXPECT_EQ(bitrate_of("62.5k"), 62500u);
  EXPECT_EQ(bitrate_of("10000"), 10000u) << "the smallest bare number";
}

TEST(Bitrate, BareNumberBelow10000IsRefusedWithTheLikelyMeaning) {
  EXPECT_EQ(bitrate_error("500"),
            "--bitrate must be at least 10000 as a bare number (bit/s), got \"500\"; did you mean 500k?");
  EXPECT_EQ(bitrate_error("9999"),
            "--bitrate must be at least 10000 as a bare number (bit/s), got \"9999\"; did you mean 9999k?");
}

TEST(Bitrate, NonsenseAndOutOfRange) {
  EXPECT_EQ(bitrate_error("fast"),
            "--bitrate must be a bit rate such as 500k, 1M or 125000 (bit/s), got \"fast\"");
  EXPECT_NE(bitrate_error(""), "");
  EXPECT_NE(bitrate_error("k"), "");
  EXPECT_NE(bitrate_error("1.5"), "") << "a fraction of a bit/s";
  EXPECT_NE(bitrate_error("1.0001k"), "");
  EXPECT_NE(bitrate_error("-5k"), "");
  EXPECT_EQ(bitrate_error("2M"), "--bitrate must be 1k..1M bit/s, got \"2M\"");
  EXPECT_NE(bitrate_error("1m"), "") << "m would be milli";
}

TEST(Bitrate, OneOfTheAllowedAndLists) {
  uint32_t bps = 0;
  EXPECT_TRUE(parse_bitrate_in("--bitrate", "250k", can_bitrates(), &bps).is_ok());
  EXPECT_EQ(bps, 250000u);
  const Status bad = parse_bitrate_in("--bitrate", "300k", can_bitrates(), &bps);
  EXPECT_EQ(bad.message(), "--bitrate must be 125k, 250k, 500k or 1M, got \"300k\"");
  std::vector<uint32_t> list;
  ASSERT_TRUE(parse_bitrate_list("--bitrates", "125k,1M,500000", can_bitrates(), &list).is_ok());
  EXPECT_EQ(list, (std::vector<uint32_t>{125000, 1000000, 500000}));
  EXPECT_EQ(parse_bitrate_list("--bitrates", "125k,500", can_bitrates(), &list).message(),
            "--bitrates must be at least 10000 as a bare number (bit/s), got \"500\"; did you mean 500k?");
  EXPECT_FALSE(parse_bitrate_list("--bitrates", "125k,", can_bitrates(), &list).is_ok());
  EXPECT_EQ(list.size(), 3u) << "untouched on failure";
}

TEST(Bitrate, TextRoundTrips) {
  for (const uint32_t bps : {10000u, 20000u, 50000u, 62500u, 125000u, 250000u, 500000u, 800000u, 1000000u}) {
    uint32_t back = 0;
    ASSERT_TRUE(parse_bitrate("x", bitrate_text(bps), 1, 1000000, &back).is_ok()) << bitrate_text(bps);
    EXPECT_EQ(back, bps);
  }
  EXPECT_EQ(bitrate_text(1000000), "1M");
  EXPECT_EQ(bitrate_text(62500), "62.5k");
}

TEST(Parity, LettersAndWordsInAnyCase) {
  const struct {
    const char* text;
    Parity parity;
  } cases[] = {{"N", Parity::kNone},    {"n", Parity::kNone}, {"none", Parity::kNone},
               {"NONE", Parity::kNone}, {"E", Parity::kEven}, {"even", Parity::kEven},
               {"Even", Parity::kEven}, {"O", Parity::kOdd},  {"o", Parity::kOdd},
               {"odd", Parity::kOdd}};
  for (const auto& c : cases) {
    Parity p = c.parity == Parity::kNone ? Parity::kOdd : Parity::kNone;
    ASSERT_TRUE(parse_parity("--parity", c.text, &p).is_ok()) << c.text;
    EXPECT_EQ(p, c.parity) << c.text;
  }
  Parity p = Parity::kNone;
  EXPECT_EQ(parse_parity("--parity", "space", &p).message(),
            "--parity must be N, E or O (none, even, odd), got \"space\"");
  EXPECT_FALSE(parse_parity("--parity", "", &p).is_ok());
  EXPECT_EQ(parity_letter(Parity::kEven), 'E');
  EXPECT_STREQ(parity_word(Parity::kOdd), "odd");
}

TEST(Uint, DigitsWithinTheRange) {
  uint64_t v = 0;
  ASSERT_TRUE(parse_uint("--n", "127", 1, 127, &v).is_ok());
  EXPECT_EQ(v, 127u);
  EXPECT_EQ(parse_uint("--n", "128", 1, 127, &v).message(), "--n must be a whole number 1..127, got \"128\"");
  EXPECT_FALSE(parse_uint("--n", "0", 1, 127, &v).is_ok());
  EXPECT_FALSE(parse_uint("--n", "-1", 0, 127, &v).is_ok());
  EXPECT_FALSE(parse_uint("--n", "0x10", 0, 127, &v).is_ok());
  EXPECT_FALSE(parse_uint("--n", "99999999999999999999", 0, UINT64_MAX, &v).is_ok()) << "overflow";
  EXPECT_EQ(v, 127u);
}

TEST(Duration, BareSecondsAndUnits) {
  uint64_t ms = 0;
  const struct {
    const char* text;
    uint64_t ms;
  } cases[] = {{"30", 30000},  {"30s", 30000},   {"1.5", 1500},   {"0.001", 1},
               {"250ms", 250}, {"2min", 120000}, {"1h", 3600000}, {"1.5s", 1500}};
  for (const auto& c : cases) {
    ASSERT_TRUE(parse_duration_ms("--duration", c.text, 1, 86400000, &ms).is_ok()) << c.text;
    EXPECT_EQ(ms, c.ms) << c.text;
  }
  EXPECT_EQ(
      parse_duration_ms("--duration", "0", 1, 86400000, &ms).message(),
      "--duration must be a duration 1 ms..86400 s (seconds, or with a unit: 250ms, 1.5s, 2min), got \"0\"");
  EXPECT_FALSE(parse_duration_ms("--duration", "0.0001", 1, 86400000, &ms).is_ok()) << "below a millisecond";
  EXPECT_FALSE(parse_duration_ms("--duration", "2d", 1, 86400000, &ms).is_ok());
  EXPECT_FALSE(parse_duration_ms("--duration", "s", 1, 86400000, &ms).is_ok());
  EXPECT_EQ(duration_text(1500), "1.5 s");
  EXPECT_EQ(duration_text(250), "250 ms");
}

}  // namespace
