// Black box: the three outcomes of a write hook (HookResult) as
// ObjectDictionary::write() answers them: accept (stored), done without
// storing (answered kSdoOk, value unchanged) and refuse (the abort code as it
// is, nothing stored). "Done" must never come out of write() as a code.
#include <gtest/gtest.h>
#include <stdint.h>

#include "canopen/od.h"
#include "canopen/od_comm.h"

namespace mb2co {
namespace test {
namespace hook_result {

#define MB2CO_HOOK_RESULT_TEST_OD(N, S)                                           \
  MB2CO_OD_DATA_TYPES(N, S)                                                       \
  N(0x2000, 0, x2000_0_accepted, U32, RW, 0, kHookApp, 7, "Stored when accepted") \
  N(0x2001, 0, x2001_0_handled, U32, RW, 0, kHookApp, 7, "Taken, never stored")   \
  N(0x2002, 0, x2002_0_refused, U32, RW, 0, kHookApp, 7, "Always refused")

#define MB2CO_HOOK_RESULT_TEST_LIMITS(L)

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(HookResult, MB2CO_HOOK_RESULT_TEST_OD)
#define MB2CO_OD_CUR_V HookResultValues
#define MB2CO_OD_CUR_P HookResultStrings
MB2CO_OD_DEFINE(HookResult, MB2CO_HOOK_RESULT_TEST_OD, MB2CO_HOOK_RESULT_TEST_LIMITS)
#undef MB2CO_OD_CUR_V
#undef MB2CO_OD_CUR_P
}  // namespace od

}  // namespace hook_result

namespace {

using namespace canopen;

struct Calls {
  int count = 0;
};

HookResult hook(void* ctx, uint8_t, uint16_t index, uint8_t, const uint8_t*, uint16_t, bool) {
  ++static_cast<Calls*>(ctx)->count;
  switch (index) {
    case 0x2000:
      return kSdoOk;
    case 0x2001:
      return HookResult::handled();
    default:
      return kAbortDeviceState;
  }
}

class WriteHookResult : public ::testing::Test {
 protected:
  void SetUp() override {
    od.restore_defaults(0x2000, 0x2002);  // 7 each: what a refused write leaves
    od.set_write_hook(&hook, &calls);
  }
  SdoAbort write(uint16_t index, uint32_t v) {
    uint8_t b[4];
    put_le32(b, v);
    return od.write(index, 0, b, 4);
  }
  uint32_t value(uint16_t index) { return od.get(od.find(index, 0)); }

  Calls calls;
  hook_result::od::HookResultValues values{};
  ObjectDictionary od{hook_result::od::HookResultDefinition, reinterpret_cast<uint8_t*>(&values)};
};

TEST_F(WriteHookResult, AcceptedValueIsStored) {
  EXPECT_EQ(write(0x2000, 42), kSdoOk);
  EXPECT_EQ(value(0x2000), 42u);
  EXPECT_EQ(calls.count, 1);
}

TEST_F(WriteHookResult, HandledWriteAnswersOkAndStoresNothing) {
  const uint16_t before = od.revision();
  EXPECT_EQ(write(0x2001, 42), kSdoOk);
  EXPECT_EQ(value(0x2001), 7u);
  EXPECT_EQ(od.revision(), before) << "nothing stored, nothing for the TPDOs";
  EXPECT_EQ(calls.count, 1);
}

TEST_F(WriteHookResult, RefusalIsTheAbortCodeAndStoresNothing) {
  EXPECT_EQ(static_cast<uint32_t>(write(0x2002, 42)), 0x08000022u);
  EXPECT_EQ(value(0x2002), 7u);
}

TEST(HookResultValue, SaysWhatTheBusMaySee) {
  EXPECT_TRUE(HookResult(kSdoOk).store());
  EXPECT_EQ(HookResult(kSdoOk).abort(), kSdoOk);
  EXPECT_FALSE(HookResult::handled().store());
  EXPECT_EQ(HookResult::handled().abort(), kSdoOk);
  EXPECT_FALSE(HookResult(kAbortStore).store());
  EXPECT_EQ(HookResult(kAbortStore).abort(), kAbortStore);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
