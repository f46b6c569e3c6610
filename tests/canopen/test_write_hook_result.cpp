// Black box: an entry's write handler (OdHandler, the slot its row names)
// and the three outcomes of a write handler (HookResult) as
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

// Three entries, each with its own handler slot, one without any; every
// handler notes the call in its owner (a Calls, bound to owner slot 1).
const uint8_t kHookAccept = canopen::kHookApp;
const uint8_t kHookHandle = canopen::kHookApp + 1;
const uint8_t kHookRefuse = canopen::kHookApp + 2;
const uint8_t kOwnerCalls = 1;

struct Calls {
  int count = 0;
  uint16_t last = 0;   ///< which handler: 0x2000, 0x2001 or 0x2002
  uint16_t index = 0;  ///< the entry it was called for
  bool apply = false;
};

struct TestHandlers {
  static canopen::HookResult note(void* calls, uint16_t handler, uint16_t index, bool apply) {
    Calls& c = *static_cast<Calls*>(calls);
    ++c.count;
    c.last = handler;
    c.index = index;
    c.apply = apply;
    return canopen::kSdoOk;
  }
  static canopen::HookResult accept(void* calls, uint16_t index, uint8_t, const uint8_t*, bool apply) {
    return note(calls, 0x2000, index, apply);
  }
  static canopen::HookResult handle(void* calls, uint16_t index, uint8_t, const uint8_t*, bool apply) {
    note(calls, 0x2001, index, apply);
    return canopen::HookResult::handled();
  }
  static canopen::HookResult refuse(void* calls, uint16_t index, uint8_t, const uint8_t*, bool apply) {
    note(calls, 0x2002, index, apply);
    return canopen::kAbortDeviceState;
  }
};

#define MB2CO_HOOK_RESULT_TEST_OD(N, S)                                              \
  MB2CO_OD_DATA_TYPES(N, S)                                                          \
  N(0x2000, 0, x2000_0_accepted, U32, RW, 0, kHookAccept, 7, "Stored when accepted") \
  N(0x2001, 0, x2001_0_handled, U32, RW, 0, kHookHandle, 7, "Taken, never stored")   \
  N(0x2002, 0, x2002_0_refused, U32, RW, 0, kHookRefuse, 7, "Always refused")        \
  N(0x2003, 0, x2003_0_plain, U32, RW, 0, kHookNone, 7, "No handler")

#define MB2CO_HOOK_RESULT_TEST_LIMITS(L)
#define MB2CO_HOOK_RESULT_TEST_HANDLERS(H)          \
  H(kHookAccept, TestHandlers::accept, kOwnerCalls) \
  H(kHookHandle, TestHandlers::handle, kOwnerCalls) \
  H(kHookRefuse, TestHandlers::refuse, kOwnerCalls)

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(HookResult, MB2CO_HOOK_RESULT_TEST_OD)
#define MB2CO_OD_CUR_V HookResultValues
#define MB2CO_OD_CUR_P HookResultStrings
MB2CO_OD_DEFINE(HookResult, MB2CO_HOOK_RESULT_TEST_OD, MB2CO_HOOK_RESULT_TEST_LIMITS,
                MB2CO_HOOK_RESULT_TEST_HANDLERS)
#undef MB2CO_OD_CUR_V
#undef MB2CO_OD_CUR_P
}  // namespace od

}  // namespace hook_result

namespace {

using namespace canopen;
using hook_result::Calls;

class WriteHookResult : public ::testing::Test {
 protected:
  void SetUp() override {
    od.restore_defaults(0x2000, 0x2003);  // 7 each: what a refused write leaves
    // Calls stands for the node as well: an OD calls handlers once its
    // node is bound (ObjectDictionary::set_owner).
    od.set_owner(kOdOwnerNode, &calls);
    od.set_owner(hook_result::kOwnerCalls, &calls);
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

// A handler per entry: each write reaches the handler its row names, and
// only that one; an entry without a handler reaches none.
TEST_F(WriteHookResult, EachWriteReachesExactlyItsEntrysHandler) {
  for (uint16_t index = 0x2000; index <= 0x2002; ++index) {
    const int before = calls.count;
    write(index, 1);
    EXPECT_EQ(calls.count, before + 1) << std::hex << index;
    EXPECT_EQ(calls.last, index) << "the handler of " << std::hex << index;
    EXPECT_EQ(calls.index, index);
    EXPECT_TRUE(calls.apply);
  }
  const int before = calls.count;
  EXPECT_EQ(write(0x2003, 42), kSdoOk);
  EXPECT_EQ(calls.count, before) << "no handler for an entry without one";
  EXPECT_EQ(value(0x2003), 42u);
}

// The check step of a request of several entries: the handler decides with
// apply false, the value is held untracked for the caller to put back.
TEST_F(WriteHookResult, CheckStepCallsTheHandlerWithoutApply) {
  uint8_t b[4];
  put_le32(b, 5);
  EXPECT_EQ(od.write_row(od.find(0x2000, 0), b, 4, false), kSdoOk);
  EXPECT_EQ(calls.count, 1);
  EXPECT_FALSE(calls.apply);
  EXPECT_EQ(static_cast<uint32_t>(od.write_row(od.find(0x2002, 0), b, 4, false)), 0x08000022u);
  EXPECT_FALSE(calls.apply);
}

// An OD without its node bound (a tool's, a test's) checks and stores
// only: no handler is called.
TEST(WriteHandlerOwner, WithoutTheNodeNoHandlerIsCalled) {
  hook_result::od::HookResultValues values{};
  ObjectDictionary od{hook_result::od::HookResultDefinition, reinterpret_cast<uint8_t*>(&values)};
  uint8_t b[4];
  put_le32(b, 9);
  EXPECT_EQ(od.write(0x2002, 0, b, 4), kSdoOk);
  EXPECT_EQ(od.get(od.find(0x2002, 0)), 9u);
}

// The handler call has a case only for the slots an OD's rows name
// (MB2CO_OD_DEFINE): the set is each named slot once, never kHookNone.
TEST(HandlerSlotsNamed, AreTheSlotsTheRowsName) {
  static constexpr OdRow kRows[] = {{0x1017, 0, 0, kHookNmt, 0, 0, 0, 0},
                                    {0x2000, 0, 0, kHookNone, 0, 0, 0, 0},
                                    {0x2001, 1, 0, kHookNodeId, 0, 0, 0, 0},
                                    {0x2001, 2, 0, kHookNodeId, 0, 0, 0, 0},
                                    {0x2100, 0, 0, kHookApp + 2, 0, 0, 0, 0}};
  constexpr uint16_t named = od_slots_named(kRows, 5);
  static_assert(named == ((1u << kHookNmt) | (1u << kHookNodeId) | (1u << (kHookApp + 2))),
                "the rows' slots");
  EXPECT_EQ(named & (1u << kHookRestartRequest), 0u);
  EXPECT_EQ(od_slots_named(kRows, 2), 1u << kHookNmt);
  EXPECT_EQ(od_slots_named(kRows + 1, 1), 0u);
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
