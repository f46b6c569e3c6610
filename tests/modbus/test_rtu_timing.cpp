#include <gtest/gtest.h>

#include "modbus/rtu_timing.h"

namespace mb2co {
namespace modbus {
namespace {

TEST(ModbusRtuTiming, CharacterTimesAtAndBelow19200) {
  // 11 bits per character: 9600 baud → 1145.8 µs; 1.5 / 3.5 of that, rounded up.
  const RtuTiming t9600 = rtu_timing(9600);
  EXPECT_EQ(t9600.char_us, 1146u);
  EXPECT_EQ(t9600.t15_us, 1719u);  // 1718.75
  EXPECT_EQ(t9600.t35_us, 4011u);  // 4010.42
  const RtuTiming t19200 = rtu_timing(19200);
  EXPECT_EQ(t19200.char_us, 573u);
  EXPECT_EQ(t19200.t15_us, 860u);   // 859.4
  EXPECT_EQ(t19200.t35_us, 2006u);  // 2005.2
}

TEST(ModbusRtuTiming, FixedAbove19200) {
  for (uint32_t baud : {19201u, 38400u, 115200u, 1000000u}) {
    const RtuTiming t = rtu_timing(baud);
    EXPECT_EQ(t.t15_us, 750u) << baud;
    EXPECT_EQ(t.t35_us, 1750u) << baud;
  }
  EXPECT_EQ(rtu_timing(115200).char_us, 96u);  // 95.5
}

TEST(ModbusRtuTiming, CharacterBitsAndBadArguments) {
  EXPECT_EQ(rtu_timing(9600, 10).char_us, 1042u);  // 8N1
  const RtuTiming zero = rtu_timing(0);
  EXPECT_GT(zero.char_us, 0u);
  EXPECT_LT(zero.t15_us, zero.t35_us);
  EXPECT_EQ(rtu_timing(9600, 0).char_us, 1146u);  // 0 bits means the default 11
}

}  // namespace
}  // namespace modbus
}  // namespace mb2co
