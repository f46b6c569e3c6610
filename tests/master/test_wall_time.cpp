// The host's wall clock as TIME_OF_DAY (mb2co-master time): the epoch, a
// date worked out by hand, the range a TIME frame can carry, and the frame's
// 6 bytes. No bus.
#include <gtest/gtest.h>

#include <vector>

#include "canopen/time_of_day.h"
#include "wall_time.h"

namespace mb2co {
namespace master {
namespace {

TEST(WallTime, TheCanopenEpochIsDayZeroAtMidnight) {
  canopen::TimeOfDay t{1, 1};
  ASSERT_TRUE(time_of_day_of_unix_ms(kCanopenEpochUnixMs, &t));
  EXPECT_EQ(t.days, 0u);
  EXPECT_EQ(t.ms, 0u);
  EXPECT_EQ(utc_text(t), "1984-01-01T00:00:00.000Z");
}

TEST(WallTime, DaysCountLeapYearsAndMsCountFromMidnight) {
  // 2000-01-01: 16 years after 1984 with 4 leap days (84, 88, 92, 96).
  canopen::TimeOfDay t{};
  ASSERT_TRUE(time_of_day_of_unix_ms(946684800000LL, &t));
  EXPECT_EQ(t.days, 16u * 365u + 4u);
  EXPECT_EQ(t.ms, 0u);
  // 2026-11-29T15:04:05.123Z (date -u -d ... +%s%3N): day 15,673.
  ASSERT_TRUE(time_of_day_of_unix_ms(1795964645123LL, &t));
  EXPECT_EQ(t.days, 15673u);
  EXPECT_EQ(t.ms, ((15u * 60u + 4u) * 60u + 5u) * 1000u + 123u);
  EXPECT_EQ(utc_text(t), "2026-11-29T15:04:05.123Z");
  // A leap day and the last ms of a day.
  EXPECT_EQ(utc_text({canopen::kMsPerDay - 1, 14669}), "2024-02-29T23:59:59.999Z");
}

TEST(WallTime, OutsideWhatTimeCanCarryIsRefused) {
  canopen::TimeOfDay t{};
  EXPECT_FALSE(time_of_day_of_unix_ms(kCanopenEpochUnixMs - 1, &t));
  EXPECT_FALSE(time_of_day_of_unix_ms(0, &t));
  const int64_t day_ms = canopen::kMsPerDay;
  ASSERT_TRUE(time_of_day_of_unix_ms(kCanopenEpochUnixMs + 65535 * day_ms + day_ms - 1, &t));
  EXPECT_EQ(t.days, 65535u);
  EXPECT_FALSE(time_of_day_of_unix_ms(kCanopenEpochUnixMs + 65536 * day_ms, &t));
}

TEST(WallTime, TheFrameCarriesMsLittleEndianThenDays) {
  uint8_t data[canopen::kTimeFrameLength];
  canopen::encode_time_of_day({0x0123ABCDu, 0x3D39u}, data);
  EXPECT_EQ(std::vector<uint8_t>(data, data + 6), (std::vector<uint8_t>{0xCD, 0xAB, 0x23, 0x01, 0x39, 0x3D}));
  // The reserved top 4 bits of the ms are sent as 0 and ignored when read.
  data[3] = 0xF1;
  const canopen::TimeOfDay back = canopen::decode_time_of_day(data);
  EXPECT_EQ(back.ms, 0x0123ABCDu);
  EXPECT_EQ(back.days, 0x3D39u);
}

TEST(WallTime, TheHostClockIsAfter1984) {
  canopen::TimeOfDay t{};
  EXPECT_TRUE(time_of_day_of_unix_ms(wall_clock_unix_ms(), &t));
  EXPECT_GT(t.days, 15000u);
}

}  // namespace
}  // namespace master
}  // namespace mb2co
