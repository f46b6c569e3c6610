// A test-only OD, defined with the same MB2CO_OD_DECLARE/MB2CO_OD_DEFINE
// machinery as the I/O node, for what the I/O node's OD does not have: a
// write-only entry (abort 06010001h) and PDO-mappable BOOLEAN and odd-sized
// entries (bit-granular mapping).
#include <gtest/gtest.h>

#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "test_fixture.h"
#include "test_od_pdos.h"

namespace mb2co {
namespace test {
namespace custom {

#define MB2CO_TEST_OD(N, S)                                                                     \
  MB2CO_OD_DATA_TYPES(N, S)                                                                     \
  MB2CO_OD_COMM_1000(N, S, 0x12345678, "custom test node", "hw", "sw", 7, 8, 9, 0)              \
  MB2CO_TEST_OD_PDOS(N)                                                                         \
  N(0x2001, 0, x2001_0_password, U32, WO, 0, kHookNone, 0, "Write-only password")               \
  S(0x2002, 0, x2002_0_text, WO, kHookNone, 8, "", "Write-only text")                           \
  N(0x2200, 0, x2200_0_highestSubIndex, U8, CONST, 0, kHookNone, 4, "Flags: highest sub-index") \
  N(0x2200, 1, x2200_1_flag1, BOOL, RW, kAttrPdo, kHookNone, 0, "Flag 1")                       \
  N(0x2200, 2, x2200_2_flag2, BOOL, RW, kAttrPdo, kHookNone, 0, "Flag 2")                       \
  N(0x2200, 3, x2200_3_flag3, BOOL, RW, kAttrPdo, kHookNone, 0, "Flag 3")                       \
  N(0x2200, 4, x2200_4_flag4, BOOL, RW, kAttrPdo, kHookNone, 0, "Flag 4")                       \
  N(0x2201, 0, x2201_0_word, U16, RW, kAttrPdo, kHookNone, 0, "Word")                           \
  N(0x2202, 0, x2202_0_signedByte, I8, RW, kAttrPdo, kHookNone, 0, "Signed byte")               \
  N(0x2203, 0, x2203_0_long, U32, RW, kAttrPdo, kHookNone, 0, "Long")

#define MB2CO_TEST_LIMITS(L)

namespace od {
using namespace ::mb2co::canopen;
MB2CO_OD_DECLARE(Test, MB2CO_TEST_OD)
#define MB2CO_OD_CUR_V TestValues
#define MB2CO_OD_CUR_P TestStrings
MB2CO_OD_DEFINE(Test, MB2CO_TEST_OD, MB2CO_TEST_LIMITS, MB2CO_OD_NO_HANDLERS)
#undef MB2CO_OD_CUR_V
#undef MB2CO_OD_CUR_P
}  // namespace od

}  // namespace custom

namespace {

using namespace canopen;

/// Node id 5 on the test-only OD, pre-operational, log empty.
class CustomOd : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 5;
  void SetUp() override {
    node.start(kId, h.now);
    bus.frames.clear();
  }
  uint32_t value(uint16_t index, uint8_t sub) { return od.get(od.find(index, sub)); }
  void set(uint16_t index, uint8_t sub, uint32_t v) { od.set(od.find(index, sub), v); }
  FrameLog bus;
  custom::od::TestValues values{};
  ObjectDictionary od{custom::od::TestDefinition, reinterpret_cast<uint8_t*>(&values)};
  Node node{od, bus.sink()};
  Harness h{node, bus};
};

TEST_F(CustomOd, ReadingAWriteOnlyObject_06010001) {
  h.expect_abort({0x40, 0x01, 0x20, 0x00}, 0x2001, 0, kAbortWriteOnly);
  h.expect_abort({0x40, 0x02, 0x20, 0x00}, 0x2002, 0, kAbortWriteOnly);
  // Writing works, and the value stays unreadable.
  EXPECT_EQ(h.write_u32(0x2001, 0, 0xCAFEF00Du), 0u);
  EXPECT_EQ(value(0x2001, 0), 0xCAFEF00Du);
  h.expect_abort({0x40, 0x01, 0x20, 0x00}, 0x2001, 0, kAbortWriteOnly);
  EXPECT_EQ(h.download_segmented(0x2002, 0, bytes_of("secret!"), true), 0u);
  h.expect_abort({0x40, 0x02, 0x20, 0x00}, 0x2002, 0, kAbortWriteOnly);
}

TEST_F(CustomOd, AWriteOnlyObjectCannotBeTransmitted) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000185u), 0u);
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x20, 0x00, 0x01, 0x20}, 0x1A00, 1, kAbortNotMappable);
}

TEST_F(CustomOd, DefaultsFollowTheNodeId) {
  EXPECT_EQ(h.read(0x1800, 1), 0x80000185u);
  EXPECT_EQ(h.read(0x1400, 1), 0x80000205u);
  EXPECT_EQ(h.read(0x1014, 0), 0x85u);
  EXPECT_EQ(h.read(0x1000, 0), 0x12345678u);
  EXPECT_EQ(h.read_string(0x1008, 0), "custom test node");
}

TEST_F(CustomOd, BitGranularTransmitMappingWithBooleansAndDummies) {
  // bit 0..2: flags 1..3 (1 bit each), bits 3..7: 5 bits of the I8 (low bits),
  // bits 8..15: UNSIGNED8 dummy (zeros), bits 16..27: 12 low bits of the U16,
  // bits 28..28: flag 4.  29 bits -> 4 bytes.
  h.map_pdo(0x1800, {0x22000101, 0x22000201, 0x22000301, 0x22020005, 0x00050008, 0x2201000C, 0x22000401});
  set(0x2200, 1, 1);
  set(0x2200, 3, 1);
  set(0x2202, 0, 0xF5);    // -11: low 5 bits 10101b
  set(0x2201, 0, 0xFABC);  // low 12 bits ABCh
  set(0x2200, 4, 1);
  h.nmt(0x01, kId);
  // byte 0: b0=1 b1=0 b2=1 | b3..7 = 10101b -> 0b10101101 = ADh
  // byte 1: dummy 00; byte 2: BCh; byte 3: low nibble Ah, bit 28 = flag 4 -> 1Ah
  EXPECT_EQ(h.take(), Frames({"<185> AD 00 BC 1A"}));
  // One BOOLEAN bit changes: the event-driven TPDO goes out again.
  set(0x2200, 2, 1);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<185> AF 00 BC 1A"}));
}

TEST_F(CustomOd, BitGranularReceiveMappingSkipsDummies) {
  // b0 flag 1, b1 flag 3, b2 flag 4, b3 flag 2, b4..11 UNSIGNED8 dummy,
  // b12..27 the U16, b28..35 the I8: 36 bits -> 5 bytes, across byte borders.
  h.map_pdo(0x1400, {0x22000101, 0x22000301, 0x22000401, 0x22000201, 0x00050008, 0x22010010, 0x22020008});
  h.nmt(0x01, kId);
  bus.frames.clear();
  set(0x2200, 3, 1);
  h.rx(F(0x205, {0xF5, 0x4F, 0x23, 0x01, 0x08}));
  EXPECT_EQ(value(0x2200, 1), 1u);
  EXPECT_EQ(value(0x2200, 3), 0u);
  EXPECT_EQ(value(0x2200, 4), 1u);
  EXPECT_EQ(value(0x2200, 2), 0u);
  EXPECT_EQ(value(0x2201, 0), 0x1234u);
  EXPECT_EQ(value(0x2202, 0), 0x80u);
  EXPECT_EQ(h.read(0x2202, 0), 0x80u);
  EXPECT_EQ(h.take(), Frames({})) << "right length: no EMCY";
}

TEST_F(CustomOd, DummyEntriesAreTypes0002To0007WithTheirOwnLength) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000185u), 0u);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 0), 0u);
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x08, 0x00, 0x01, 0x00}, 0x1A00, 1, kAbortNotMappable);
  // 0001h (BOOLEAN) has no kAttrPdo in the data-type table: not a dummy here.
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x01, 0x00, 0x01, 0x00}, 0x1A00, 1, kAbortNotMappable);
  EXPECT_EQ(h.write_u32(0x1A00, 1, 0x00020008u), 0u);
  EXPECT_EQ(h.write_u32(0x1A00, 2, 0x00030010u), 0u);
  EXPECT_EQ(h.write_u32(0x1A00, 3, 0x00040020u), 0u);
  EXPECT_EQ(h.write_u32(0x1A00, 4, 0x00060010u), 0u);
  h.expect_abort({0x2F, 0x00, 0x1A, 0x00, 4, 0, 0, 0}, 0x1A00, 0, kAbortMapLength);  // 72 bits
  EXPECT_EQ(h.write_u8(0x1A00, 0, 3), 0u);                                           // 56 bits
}

TEST_F(CustomOd, BooleanWritesBySdoAreZeroOrOne) {
  EXPECT_EQ(h.write_u8(0x2200, 1, 1), 0u);
  h.expect_abort({0x2F, 0x00, 0x22, 0x01, 0x03, 0, 0, 0}, 0x2200, 1, kAbortInvalidValue);
  EXPECT_EQ(value(0x2200, 1), 1u);
}

TEST_F(CustomOd, SixtyFourBitsOfMappingFillEightBytes) {
  // 32 + 16 + 8 + 4 x 1 + 4 (low nibble of the U16 again) = 64 bits.
  h.map_pdo(0x1800,
            {0x22030020, 0x22010010, 0x22020008, 0x22000101, 0x22000201, 0x22000301, 0x22000401, 0x22010004});
  set(0x2203, 0, 0x44332211);
  set(0x2201, 0, 0x6655);
  set(0x2202, 0, 0x77);
  set(0x2200, 4, 1);
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<185> 11 22 33 44 55 66 77 58"}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
