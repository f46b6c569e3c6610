// Limits beyond the data type (OdLimit rows) on every kind of entry: signed
// values sign-extended from 1, 2 and 4 bytes, unsigned values above
// INT32_MAX, and both ends of each range. The I/O node's OD has only unsigned
// limits, so a test-only OD defines the rest.
#include <gtest/gtest.h>
#include <stdint.h>

#include "canopen/od.h"
#include "canopen/od_comm.h"

namespace mb2co {
namespace test {
namespace limits {

#define MB2CO_LIMITS_TEST_OD(N, S)                                                     \
  MB2CO_OD_DATA_TYPES(N, S)                                                            \
  N(0x2000, 0, x2000_0_i8Limited, I8, RW, 0, kHookNone, 0, "I8 in -10..20")            \
  N(0x2001, 0, x2001_0_i16Limited, I16, RW, 0, kHookNone, 0, "I16 in -1000..1000")     \
  N(0x2002, 0, x2002_0_i32Limited, I32, RW, 0, kHookNone, 0, "I32 in -100000..100000") \
  N(0x2003, 0, x2003_0_u32Limited, U32, RW, 0, kHookNone, 0, "U32 in 0..5000")         \
  N(0x2004, 0, x2004_0_u8Limited, U8, RW, 0, kHookNone, 1, "U8 in 1..250")             \
  N(0x2005, 0, x2005_0_i16Unlimited, I16, RW, 0, kHookNone, 0, "I16 without limits")

#define MB2CO_LIMITS_TEST_LIMITS(L) \
  L(0x2000, 0, -10, 20)             \
  L(0x2001, 0, -1000, 1000)         \
  L(0x2002, 0, -100000, 100000)     \
  L(0x2003, 0, 0, 5000)             \
  L(0x2004, 0, 1, 250)

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(Limits, MB2CO_LIMITS_TEST_OD)
#define MB2CO_OD_CUR_V LimitsValues
#define MB2CO_OD_CUR_P LimitsStrings
MB2CO_OD_DEFINE(Limits, MB2CO_LIMITS_TEST_OD, MB2CO_LIMITS_TEST_LIMITS, MB2CO_OD_NO_HANDLERS)
#undef MB2CO_OD_CUR_V
#undef MB2CO_OD_CUR_P
}  // namespace od

}  // namespace limits

namespace {

using namespace canopen;

class OdLimits : public ::testing::Test {
 protected:
  /// Writes the low `len` bytes of `v` (little-endian, as on the bus).
  uint32_t write(uint16_t index, uint32_t v, uint16_t len) {
    uint8_t b[4] = {static_cast<uint8_t>(v), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v >> 16),
                    static_cast<uint8_t>(v >> 24)};
    return od.write(index, 0, b, len);
  }
  uint32_t value(uint16_t index) { return od.get(od.find(index, 0)); }

  limits::od::LimitsValues values{};
  ObjectDictionary od{limits::od::LimitsDefinition, reinterpret_cast<uint8_t*>(&values)};
};

TEST_F(OdLimits, SignedByteIsSignExtended) {
  EXPECT_EQ(write(0x2000, 0xF5, 1), kAbortValueTooLow);  // -11
  EXPECT_EQ(write(0x2000, 0x80, 1), kAbortValueTooLow);  // -128
  EXPECT_EQ(write(0x2000, 21, 1), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2000, 0x7F, 1), kAbortValueTooHigh);
  EXPECT_EQ(value(0x2000), 0u) << "a refused value is not stored";
  EXPECT_EQ(write(0x2000, 0xF6, 1), kSdoOk);  // -10
  EXPECT_EQ(value(0x2000), 0xF6u);
  EXPECT_EQ(write(0x2000, 20, 1), kSdoOk);
  EXPECT_EQ(value(0x2000), 20u);
}

TEST_F(OdLimits, SignedWordIsSignExtended) {
  EXPECT_EQ(write(0x2001, static_cast<uint16_t>(-1001), 2), kAbortValueTooLow);
  EXPECT_EQ(write(0x2001, 0x8000, 2), kAbortValueTooLow);
  EXPECT_EQ(write(0x2001, 1001, 2), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2001, 0x7FFF, 2), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2001, static_cast<uint16_t>(-1000), 2), kSdoOk);
  EXPECT_EQ(value(0x2001), static_cast<uint16_t>(-1000));
  EXPECT_EQ(write(0x2001, 1000, 2), kSdoOk);
  EXPECT_EQ(value(0x2001), 1000u);
}

TEST_F(OdLimits, SignedLongUsesAllFourBytes) {
  EXPECT_EQ(write(0x2002, static_cast<uint32_t>(-100001), 4), kAbortValueTooLow);
  EXPECT_EQ(write(0x2002, 0x80000000u, 4), kAbortValueTooLow);
  EXPECT_EQ(write(0x2002, 100001, 4), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2002, 0x7FFFFFFFu, 4), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2002, static_cast<uint32_t>(-100000), 4), kSdoOk);
  EXPECT_EQ(value(0x2002), static_cast<uint32_t>(-100000));
  EXPECT_EQ(write(0x2002, 100000, 4), kSdoOk);
}

TEST_F(OdLimits, UnsignedAboveInt32MaxIsTooHigh) {
  EXPECT_EQ(write(0x2003, 5001, 4), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2003, 0x80000000u, 4), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2003, 0xFFFFFFFFu, 4), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2003, 5000, 4), kSdoOk);
  EXPECT_EQ(write(0x2003, 0, 4), kSdoOk);
  EXPECT_EQ(value(0x2003), 0u);
}

TEST_F(OdLimits, UnsignedByteIsNotSignExtended) {
  EXPECT_EQ(write(0x2004, 0, 1), kAbortValueTooLow);
  EXPECT_EQ(write(0x2004, 251, 1), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2004, 0xFF, 1), kAbortValueTooHigh);
  EXPECT_EQ(write(0x2004, 250, 1), kSdoOk);
  EXPECT_EQ(value(0x2004), 250u);
}

TEST_F(OdLimits, EntriesWithoutLimitsTakeTheirWholeRange) {
  EXPECT_EQ(write(0x2005, 0x8000, 2), kSdoOk);
  EXPECT_EQ(write(0x2005, 0x7FFF, 2), kSdoOk);
  EXPECT_EQ(value(0x2005), 0x7FFFu);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
