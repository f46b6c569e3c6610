// Every CiA 301 SDO abort code the node can give, each provoked by a request
// that deserves it. Each check compares the whole abort frame (80h, index,
// sub-index, code little-endian) and proves the OD unchanged afterwards.
// 06010001h (write-only object) needs an OD with such an entry: see
// test_custom_od.cpp.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using SdoAbort = IoNodeTest;

// ---- 05030000h toggle bit not alternated -----------------------------------
TEST_F(SdoAbort, ToggleNotAlternatedInDownload_05030000) {
  ASSERT_EQ(h.check_response(h.sdo({0x21, 0x00, 0x20, 0x00, 14, 0, 0, 0}), 0x60, 0x2000, 0), 0u);
  EXPECT_EQ(to_string(h.sdo({0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'})), "<583> 20 00 00 00 00 00 00 00");
  h.expect_abort({0x01, 'h', 'i', 'j', 'k', 'l', 'm', 'n'}, 0x2000, 0, kAbortToggle);  // t must be 1
  EXPECT_EQ(text(0x2000, 0), "");
  // The transfer is gone: a segment now is out of sequence.
  h.expect_abort({0x11, 'h', 'i', 'j', 'k', 'l', 'm', 'n'}, 0x2000, 0, kAbortCommand);
}

TEST_F(SdoAbort, ToggleNotAlternatedInUpload_05030000) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  h.expect_abort({0x70}, 0x1008, 0, kAbortToggle);  // first request must have t = 0
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 6D 62 32 63 6F 20 49");
  h.expect_abort({0x60}, 0x1008, 0, kAbortToggle);  // repeated instead of toggled
}

// ---- 05040000h SDO protocol timed out ----------------------------------------
TEST_F(SdoAbort, ServerTimeoutDuringDownload_05040000) {
  ASSERT_EQ(h.check_response(h.sdo({0x21, 0x00, 0x20, 0x00, 10, 0, 0, 0}), 0x60, 0x2000, 0), 0u);
  EXPECT_EQ(to_string(h.sdo({0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'})), "<583> 20 00 00 00 00 00 00 00");
  const std::vector<Bytes> before = od_snapshot(od());
  h.run_us(999000, 1000);  // 1 s server timeout from the last request
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({abort_frame(kId, 0x2000, 0, kAbortTimeout)}));
  h.run_us(3000000, 10000);
  EXPECT_EQ(h.take(), Frames({})) << "one abort, once";
  EXPECT_TRUE(od_snapshot(od()) == before);
  h.expect_abort({0x10, 'h', 'i', 'j', 0, 0, 0, 0}, 0x2000, 0, kAbortCommand);
}

TEST_F(SdoAbort, ServerTimeoutDuringUpload_05040000) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  h.advance_us(1000000);
  EXPECT_EQ(h.take(), Frames({abort_frame(kId, 0x1008, 0, kAbortTimeout)}));
}

TEST_F(SdoAbort, NoTimeoutWithoutATransferInProgress) {
  EXPECT_EQ(h.read(0x1000, 0), 0x00030191u);
  h.run_us(5000000, 10000);
  EXPECT_EQ(h.take(), Frames({}));
}

// ---- 05040001h command specifier not valid or unknown ----------------------
TEST_F(SdoAbort, BlockAndUnknownCommandSpecifiers_05040001) {
  // ccs 5 (block upload), 6 (block download), 7 (undefined): refused with
  // the multiplexer of the request.
  h.expect_abort({0xA0, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0}, 0x1008, 0, kAbortCommand);
  h.expect_abort({0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0}, 0x1008, 0, kAbortCommand);
  h.expect_abort({0xC2, 0x00, 0x20, 0x00, 0x05, 0, 0, 0}, 0x2000, 0, kAbortCommand);
  h.expect_abort({0xC6, 0x00, 0x20, 0x00, 0x05, 0, 0, 0}, 0x2000, 0, kAbortCommand);
  h.expect_abort({0xE0, 0x34, 0x12, 0x56, 0, 0, 0, 0}, 0x1234, 0x56, kAbortCommand);
  h.expect_abort({0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF}, 0xFFFF, 0xFF, kAbortCommand);
}

TEST_F(SdoAbort, SegmentWithoutInitiate_05040001) {
  // Nothing was initiated yet: the abort carries multiplexer 0000h/00h.
  h.expect_abort({0x00, 1, 2, 3, 4, 5, 6, 7}, 0x0000, 0, kAbortCommand);  // download segment
  h.expect_abort({0x60}, 0x0000, 0, kAbortCommand);                       // upload segment
}

TEST_F(SdoAbort, SegmentOfTheOtherDirection_05040001) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  h.expect_abort({0x00, 1, 2, 3, 4, 5, 6, 7}, 0x1008, 0, kAbortCommand);
  ASSERT_EQ(h.check_response(h.sdo({0x21, 0x00, 0x20, 0x00, 10, 0, 0, 0}), 0x60, 0x2000, 0), 0u);
  h.expect_abort({0x60}, 0x2000, 0, kAbortCommand);
}

TEST_F(SdoAbort, SegmentAfterAnExpeditedTransfer_05040001) {
  ASSERT_EQ(h.write_u16(0x2101, 0, 20), 0u);
  h.expect_abort({0x00, 1, 2, 3, 4, 5, 6, 7}, 0x2101, 0, kAbortCommand);
  EXPECT_EQ(value(0x2101, 0), 20u);
}

// ---- 06010000h unsupported access -------------------------------------------
TEST_F(SdoAbort, MappingWrittenWhilePdoValid_06010000) {
  // TPDO1 and RPDO1 are valid by default (default connection set).
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x08, 0x01, 0x00, 0x60}, 0x1A00, 1, kAbortUnsupported);
  h.expect_abort({0x2F, 0x00, 0x1A, 0x00, 0x01, 0, 0, 0}, 0x1A00, 0, kAbortUnsupported);
  h.expect_abort({0x23, 0x00, 0x16, 0x02, 0x08, 0x01, 0x00, 0x62}, 0x1600, 2, kAbortUnsupported);
  h.expect_abort({0x2F, 0x00, 0x16, 0x00, 0x00, 0, 0, 0}, 0x1600, 0, kAbortUnsupported);
}

TEST_F(SdoAbort, MappingEntryWrittenWhileSub0NotZero_06010000) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);  // disabled
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x08, 0x02, 0x00, 0x60}, 0x1A00, 1, kAbortUnsupported);
  h.expect_abort({0x23, 0x00, 0x1A, 0x03, 0x08, 0x00, 0x01, 0x10}, 0x1A00, 3, kAbortUnsupported);
  ASSERT_EQ(h.write_u32(0x1400, 1, 0x80000203u), 0u);
  h.expect_abort({0x23, 0x00, 0x16, 0x01, 0x08, 0x02, 0x00, 0x62}, 0x1600, 1, kAbortUnsupported);
}

// ---- 06010002h attempt to write a read-only object ---------------------------
TEST_F(SdoAbort, WriteReadOnlyOrConst_06010002) {
  h.expect_abort({0x2F, 0x01, 0x10, 0x00, 0x01, 0, 0, 0}, 0x1001, 0, kAbortReadOnly);
  h.expect_abort({0x23, 0x18, 0x10, 0x01, 0x01, 0, 0, 0}, 0x1018, 1, kAbortReadOnly);
  h.expect_abort({0x2F, 0x18, 0x10, 0x00, 0x05, 0, 0, 0}, 0x1018, 0, kAbortReadOnly);
  h.expect_abort({0x23, 0x18, 0x10, 0x04, 0x01, 0, 0, 0}, 0x1018, 4, kAbortReadOnly);
  h.expect_abort({0x23, 0x00, 0x10, 0x00, 0x01, 0, 0, 0}, 0x1000, 0, kAbortReadOnly);
  h.expect_abort({0x2F, 0x00, 0x60, 0x01, 0x01, 0, 0, 0}, 0x6000, 1, kAbortReadOnly);
  h.expect_abort({0x2F, 0x00, 0x62, 0x00, 0x03, 0, 0, 0}, 0x6200, 0, kAbortReadOnly);
  h.expect_abort({0x23, 0x03, 0x10, 0x01, 0x00, 0, 0, 0}, 0x1003, 1, kAbortReadOnly);
  h.expect_abort({0x23, 0x00, 0x12, 0x01, 0x04, 0x06, 0, 0}, 0x1200, 1, kAbortReadOnly);
  // Segmented: refused at the initiate, before any data.
  h.expect_abort({0x21, 0x08, 0x10, 0x00, 5, 0, 0, 0}, 0x1008, 0, kAbortReadOnly);
  h.expect_abort({0x20, 0x09, 0x10, 0x00, 0, 0, 0, 0}, 0x1009, 0, kAbortReadOnly);
}

// ---- 06020000h object does not exist ------------------------------------------
TEST_F(SdoAbort, NoObject_06020000) {
  h.expect_abort({0x40, 0x55, 0x55, 0x00}, 0x5555, 0, kAbortNoObject);
  h.expect_abort({0x23, 0x55, 0x55, 0x00, 1, 2, 3, 4}, 0x5555, 0, kAbortNoObject);
  h.expect_abort({0x21, 0x55, 0x55, 0x00, 8, 0, 0, 0}, 0x5555, 0, kAbortNoObject);
  h.expect_abort({0x40, 0x02, 0x10, 0x00}, 0x1002, 0, kAbortNoObject);
  h.expect_abort({0x40, 0x04, 0x18, 0x00}, 0x1804, 0, kAbortNoObject);  // only 4 TPDOs
  h.expect_abort({0x40, 0x00, 0x00, 0x00}, 0x0000, 0, kAbortNoObject);
  h.expect_abort({0x40, 0xFF, 0xFF, 0xFF}, 0xFFFF, 0xFF, kAbortNoObject);
}

// ---- 06040041h object cannot be mapped ---------------------------------------
TEST_F(SdoAbort, UnmappableObjectIntoPdo_06040041) {
  ASSERT_EQ(h.write_u32(0x1801, 1, 0x80000283u), 0u);  // TPDO2 stays disabled
  ASSERT_EQ(h.write_u8(0x1A01, 0, 0), 0u);
  h.expect_abort({0x23, 0x01, 0x1A, 0x01, 0x10, 0x00, 0x17, 0x10}, 0x1A01, 1, kAbortNotMappable);  // 1017h
  h.expect_abort({0x23, 0x01, 0x1A, 0x01, 0x10, 0x00, 0x01, 0x21}, 0x1A01, 1, kAbortNotMappable);  // 2101h
  // Longer than the object.
  h.expect_abort({0x23, 0x01, 0x1A, 0x01, 0x10, 0x01, 0x00, 0x60}, 0x1A01, 1, kAbortNotMappable);
  // Zero length.
  h.expect_abort({0x23, 0x01, 0x1A, 0x01, 0x00, 0x01, 0x00, 0x60}, 0x1A01, 1, kAbortNotMappable);
  // A dummy entry whose length is not its type's.
  h.expect_abort({0x23, 0x01, 0x1A, 0x01, 0x10, 0x00, 0x05, 0x00}, 0x1A01, 1, kAbortNotMappable);
  // A read-only input cannot be received by an RPDO.
  ASSERT_EQ(h.write_u8(0x1601, 0, 0), 0u);
  h.expect_abort({0x23, 0x01, 0x16, 0x01, 0x08, 0x01, 0x00, 0x60}, 0x1601, 1, kAbortNotMappable);
  // BOOLEAN 2100h is not PDO-mappable in this OD.
  h.expect_abort({0x23, 0x01, 0x16, 0x01, 0x01, 0x00, 0x00, 0x21}, 0x1601, 1, kAbortNotMappable);
}

// ---- 06040042h mapping exceeds the PDO length --------------------------------
TEST_F(SdoAbort, MoreThanEightEntriesOrSixtyFourBits_06040042) {
  ASSERT_EQ(h.write_u32(0x1801, 1, 0x80000283u), 0u);
  h.expect_abort({0x2F, 0x01, 0x1A, 0x00, 9, 0, 0, 0}, 0x1A01, 0, kAbortMapLength);
  h.expect_abort({0x2F, 0x01, 0x1A, 0x00, 0xFF, 0, 0, 0}, 0x1A01, 0, kAbortMapLength);
  ASSERT_EQ(h.write_u8(0x1A01, 0, 0), 0u);
  // 3 x UNSIGNED32 dummies = 96 bits.
  for (uint8_t s = 1; s <= 3; ++s) ASSERT_EQ(h.write_u32(0x1A01, s, 0x00070020u), 0u);
  EXPECT_EQ(h.write_u8(0x1A01, 0, 2), 0u);  // 64 bits fit
  ASSERT_EQ(h.write_u8(0x1A01, 0, 0), 0u);
  h.expect_abort({0x2F, 0x01, 0x1A, 0x00, 3, 0, 0, 0}, 0x1A01, 0, kAbortMapLength);
  // Same for an RPDO.
  ASSERT_EQ(h.write_u32(0x1401, 1, 0x80000303u), 0u);
  h.expect_abort({0x2F, 0x01, 0x16, 0x00, 9, 0, 0, 0}, 0x1601, 0, kAbortMapLength);
}

// ---- 06040043h general parameter incompatibility ------------------------------
TEST_F(SdoAbort, TwoHeartbeatConsumersForOneNode_06040043) {
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);  // node 5, 100 ms
  h.expect_abort({0x23, 0x16, 0x10, 0x02, 0xC8, 0x00, 0x05, 0x00}, 0x1016, 2, kAbortIncompatible);
  h.expect_abort({0x23, 0x16, 0x10, 0x04, 0x01, 0x00, 0x05, 0x00}, 0x1016, 4, kAbortIncompatible);
  // Rewriting the same sub-index, or a second entry with time 0, is fine.
  EXPECT_EQ(h.write_u32(0x1016, 1, 0x000500C8u), 0u);
  EXPECT_EQ(h.write_u32(0x1016, 2, 0x00050000u), 0u);
}

// ---- 06070010h data type / length does not match ------------------------------
TEST_F(SdoAbort, SegmentedDownloadShorterOrLongerThanAnnounced_06070010) {
  ASSERT_EQ(h.check_response(h.sdo({0x21, 0x00, 0x20, 0x00, 5, 0, 0, 0}), 0x60, 0x2000, 0), 0u);
  h.expect_abort({0x09, 'a', 'b', 'c', 0, 0, 0, 0}, 0x2000, 0, kAbortTypeMismatch);  // 3 of 5
  EXPECT_EQ(text(0x2000, 0), "");
  ASSERT_EQ(h.check_response(h.sdo({0x21, 0x00, 0x20, 0x00, 8, 0, 0, 0}), 0x60, 0x2000, 0), 0u);
  EXPECT_EQ(to_string(h.sdo({0x00, 'a', 'b', 'c', 'd', 'e', 'f', 'g'})), "<583> 20 00 00 00 00 00 00 00");
  h.expect_abort({0x13, 'h', 'i', 'j', 'k', 'l', 'm', 0}, 0x2000, 0, kAbortTypeMismatch);  // 13 of 8
  EXPECT_EQ(text(0x2000, 0), "");
}

// ---- 06070012h length too high --------------------------------------------------
TEST_F(SdoAbort, TooLong_06070012) {
  // Five bytes to a U32, announced: refused at the initiate.
  h.expect_abort({0x21, 0x06, 0x10, 0x00, 5, 0, 0, 0}, 0x1006, 0, kAbortTooLong);
  // Five bytes to a U32, not announced: refused at the last segment.
  ASSERT_EQ(h.check_response(h.sdo({0x20, 0x06, 0x10, 0x00}), 0x60, 0x1006, 0), 0u);
  h.expect_abort({0x05, 1, 2, 3, 4, 5, 0, 0}, 0x1006, 0, kAbortTooLong);
  EXPECT_EQ(value(0x1006, 0), 0u);
  // A 25-character string into 2000h (24 characters).
  h.expect_abort({0x21, 0x00, 0x20, 0x00, 25, 0, 0, 0}, 0x2000, 0, kAbortTooLong);
  ASSERT_EQ(h.check_response(h.sdo({0x20, 0x00, 0x20, 0x00}), 0x60, 0x2000, 0), 0u);
  for (uint8_t k = 0; k < 3; ++k) {
    const uint8_t t = static_cast<uint8_t>((k & 1) << 4);
    EXPECT_EQ(h.check_response(h.sdo({t, 'x', 'x', 'x', 'x', 'x', 'x', 'x'}), uint8_t(0x20 | t), 0, 0, false),
              0u);
  }
  h.expect_abort({0x17, 'y', 'y', 'y', 'y', 0, 0, 0}, 0x2000, 0, kAbortTooLong);  // 21 + 4 = 25
  EXPECT_EQ(text(0x2000, 0), "");
  // Expedited 4 bytes (size indicated) to a U8 / U16.
  h.expect_abort({0x23, 0x0D, 0x10, 0x00, 1, 0, 0, 0}, 0x100D, 0, kAbortTooLong);
  h.expect_abort({0x27, 0x01, 0x21, 0x00, 1, 0, 0, 0}, 0x2101, 0, kAbortTooLong);
  // More segments than the server buffers (32 bytes), no size indicated.
  ASSERT_EQ(h.check_response(h.sdo({0x20, 0x00, 0x20, 0x00}), 0x60, 0x2000, 0), 0u);
  for (uint8_t k = 0; k < 4; ++k) {
    const uint8_t t = static_cast<uint8_t>((k & 1) << 4);
    EXPECT_EQ(h.check_response(h.sdo({t, 'x', 'x', 'x', 'x', 'x', 'x', 'x'}), uint8_t(0x20 | t), 0, 0, false),
              0u);
  }
  h.expect_abort({0x00, 'z', 'z', 'z', 'z', 'z', 'z', 'z'}, 0x2000, 0, kAbortTooLong);
}

// ---- 06070013h length too low ----------------------------------------------------
TEST_F(SdoAbort, TooShort_06070013) {
  h.expect_abort({0x2B, 0x06, 0x10, 0x00, 0x10, 0x27, 0, 0}, 0x1006, 0, kAbortTooShort);  // 2 to U32
  h.expect_abort({0x2F, 0x06, 0x10, 0x00, 0x10, 0, 0, 0}, 0x1006, 0, kAbortTooShort);     // 1 to U32
  h.expect_abort({0x2F, 0x01, 0x21, 0x00, 0x10, 0, 0, 0}, 0x2101, 0, kAbortTooShort);     // 1 to U16
  h.expect_abort({0x21, 0x06, 0x10, 0x00, 2, 0, 0, 0}, 0x1006, 0, kAbortTooShort);        // announced
  ASSERT_EQ(h.check_response(h.sdo({0x20, 0x06, 0x10, 0x00}), 0x60, 0x1006, 0), 0u);
  h.expect_abort({0x0B, 1, 2, 0, 0, 0, 0, 0}, 0x1006, 0, kAbortTooShort);  // 2 bytes sent
}

// ---- 06090011h sub-index does not exist ---------------------------------------------
TEST_F(SdoAbort, NoSubindex_06090011) {
  h.expect_abort({0x40, 0x18, 0x10, 0x05}, 0x1018, 5, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x18, 0x04}, 0x1800, 4, kAbortNoSubindex);  // reserved
  h.expect_abort({0x2F, 0x00, 0x18, 0x04, 0, 0, 0, 0}, 0x1800, 4, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x14, 0x04}, 0x1400, 4, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x14, 0x06}, 0x1400, 6, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x18, 0x07}, 0x1800, 7, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x1A, 0x09}, 0x1A00, 9, kAbortNoSubindex);
  h.expect_abort({0x40, 0x16, 0x10, 0x05}, 0x1016, 5, kAbortNoSubindex);
  h.expect_abort({0x40, 0x03, 0x10, 0x05}, 0x1003, 5, kAbortNoSubindex);
  h.expect_abort({0x23, 0x17, 0x10, 0x01, 0, 0, 0, 0}, 0x1017, 1, kAbortNoSubindex);
  h.expect_abort({0x40, 0x00, 0x60, 0x03}, 0x6000, 3, kAbortNoSubindex);
}

// ---- 06090030h invalid value -----------------------------------------------------------
TEST_F(SdoAbort, InvalidValue_06090030) {
  h.expect_abort({0x2F, 0x03, 0x10, 0x00, 1, 0, 0, 0}, 0x1003, 0, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x18, 0x02, 245, 0, 0, 0}, 0x1800, 2, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x18, 0x02, 241, 0, 0, 0}, 0x1800, 2, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x18, 0x02, 251, 0, 0, 0}, 0x1800, 2, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x14, 0x02, 252, 0, 0, 0}, 0x1400, 2, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x14, 0x02, 241, 0, 0, 0}, 0x1400, 2, kAbortInvalidValue);
  // COB-ID of a valid PDO changed without disabling it first.
  h.expect_abort({0x23, 0x00, 0x18, 0x01, 0x84, 0x01, 0, 0}, 0x1800, 1, kAbortInvalidValue);
  h.expect_abort({0x23, 0x00, 0x14, 0x01, 0x04, 0x02, 0, 0}, 0x1400, 1, kAbortInvalidValue);
  // 29-bit CAN-IDs (bit 29) are not supported.
  h.expect_abort({0x23, 0x00, 0x18, 0x01, 0x83, 0x01, 0x00, 0x20}, 0x1800, 1, kAbortInvalidValue);
  // Restricted CAN-IDs (CiA 301 §7.3.5) for a PDO being made valid.
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  for (uint32_t id : {0x000u, 0x001u, 0x07Fu, 0x101u, 0x180u, 0x581u, 0x5FFu, 0x601u, 0x67Fu, 0x6E0u, 0x6FFu,
                      0x701u, 0x7FFu}) {
    h.expect_abort({0x23, 0x00, 0x18, 0x01, static_cast<uint8_t>(id), static_cast<uint8_t>(id >> 8), 0, 0},
                   0x1800, 1, kAbortInvalidValue);
  }
  // Inhibit time and SYNC start value only while the PDO is not valid.
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x00000183u), 0u);
  h.expect_abort({0x2B, 0x00, 0x18, 0x03, 10, 0, 0, 0}, 0x1800, 3, kAbortInvalidValue);
  h.expect_abort({0x2F, 0x00, 0x18, 0x06, 2, 0, 0, 0}, 0x1800, 6, kAbortInvalidValue);
  // BOOLEAN takes 0 or 1 only.
  h.expect_abort({0x2F, 0x00, 0x21, 0x00, 2, 0, 0, 0}, 0x2100, 0, kAbortInvalidValue);
  // 1016h reserved bits 24..31, and node ids above 127.
  h.expect_abort({0x23, 0x16, 0x10, 0x01, 0x64, 0x00, 0x05, 0x01}, 0x1016, 1, kAbortInvalidValue);
  h.expect_abort({0x23, 0x16, 0x10, 0x01, 0x64, 0x00, 0x80, 0x00}, 0x1016, 1, kAbortInvalidValue);
  // EMCY COB-ID changed while valid; 29-bit.
  h.expect_abort({0x23, 0x14, 0x10, 0x00, 0x90, 0x00, 0, 0}, 0x1014, 0, kAbortInvalidValue);
  h.expect_abort({0x23, 0x14, 0x10, 0x00, 0x83, 0x00, 0, 0x20}, 0x1014, 0, kAbortInvalidValue);
  // 1019h = 1 is no counter.
  h.expect_abort({0x2F, 0x19, 0x10, 0x00, 1, 0, 0, 0}, 0x1019, 0, kAbortInvalidValue);
}

TEST_F(SdoAbort, RestrictedCanIdsForSyncAndEmcy_06090030) {
  // CiA 301 §7.3.5: restricted CAN-IDs are not used by SYNC, EMCY, PDO or SDO.
  // A SYNC COB-ID of 603h would take the SDO server's requests away.
  h.expect_abort({0x23, 0x05, 0x10, 0x00, 0x03, 0x06, 0, 0}, 0x1005, 0, kAbortInvalidValue);
  h.expect_abort({0x23, 0x05, 0x10, 0x00, 0x00, 0x00, 0, 0}, 0x1005, 0, kAbortInvalidValue);
  h.expect_abort({0x23, 0x05, 0x10, 0x00, 0x03, 0x07, 0, 0}, 0x1005, 0, kAbortInvalidValue);
  ASSERT_EQ(h.write_u32(0x1014, 0, 0x80000083u), 0u);
  h.expect_abort({0x23, 0x14, 0x10, 0x00, 0x03, 0x07, 0, 0}, 0x1014, 0, kAbortInvalidValue);
  h.expect_abort({0x23, 0x14, 0x10, 0x00, 0x03, 0x00, 0, 0}, 0x1014, 0, kAbortInvalidValue);
  // Legal ones are taken.
  EXPECT_EQ(h.write_u32(0x1005, 0, 0x00000090u), 0u);
  EXPECT_EQ(h.write_u32(0x1014, 0, 0x00000093u), 0u);
  EXPECT_EQ(h.read(0x1005, 0), 0x90u);
  EXPECT_EQ(h.read(0x1014, 0), 0x93u);
}

// ---- 06090031h / 06090032h value too high / too low ---------------------------------
TEST_F(SdoAbort, ValueAboveOrBelowLimits_06090031_06090032) {
  h.expect_abort({0x2B, 0x01, 0x21, 0x00, 251, 0, 0, 0}, 0x2101, 0, kAbortValueTooHigh);
  h.expect_abort({0x2B, 0x01, 0x21, 0x00, 0xFF, 0xFF, 0, 0}, 0x2101, 0, kAbortValueTooHigh);
  h.expect_abort({0x2B, 0x01, 0x21, 0x00, 0, 0, 0, 0}, 0x2101, 0, kAbortValueTooLow);
  EXPECT_EQ(h.write_u16(0x2101, 0, 250), 0u);
  EXPECT_EQ(h.write_u16(0x2101, 0, 1), 0u);
  // 1019h: 2..240 (CiA 301 §7.5.2.41).
  h.expect_abort({0x2F, 0x19, 0x10, 0x00, 241, 0, 0, 0}, 0x1019, 0, kAbortValueTooHigh);
  h.expect_abort({0x2F, 0x19, 0x10, 0x00, 255, 0, 0, 0}, 0x1019, 0, kAbortValueTooHigh);
  EXPECT_EQ(h.write_u8(0x1019, 0, 240), 0u);
  EXPECT_EQ(h.write_u8(0x1019, 0, 2), 0u);
  EXPECT_EQ(h.write_u8(0x1019, 0, 0), 0u);
}

// ---- 08000000h / 08000020h: storing parameters -----------------------------------------
struct FailingStorage {
  static bool read(void*, uint16_t, uint8_t*, uint16_t) { return false; }
  static bool write(void*, uint16_t, const uint8_t*, uint16_t) { return false; }
};

// "save" is answered before it runs (it takes passes: ParamSave); its
// failure is EMCY 5530h, not an abort. "load" is one write: aborted.
TEST_F(SdoAbort, SaveWithFailingStorage_08000000) {
  const ParamStorage st = {&FailingStorage::read, &FailingStorage::write, nullptr, nullptr, nullptr};
  io.node().set_storage(&st);
  h.nmt(0x82, kId);  // 1010h reads the capability from the next reset on
  bus.frames.clear();
  EXPECT_EQ(h.read(0x1010, 1), 1u);
  EXPECT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  h.advance_us(100);
  EXPECT_FALSE(io.node().saving());
  EXPECT_TRUE(io.node().emcy().active(0x5530)) << "the failed save is reported";
  h.expect_abort({0x23, 0x11, 0x10, 0x01, 'l', 'o', 'a', 'd'}, 0x1011, 1, kAbortGeneral);
}

TEST_F(SdoAbort, SaveWithWrongSignatureOrWithoutStorage_08000020) {
  EXPECT_EQ(h.read(0x1010, 1), 0u) << "no storage: nothing saved on command";
  h.expect_abort({0x23, 0x10, 0x10, 0x01, 's', 'a', 'v', 'e'}, 0x1010, 1, kAbortStore);
  h.expect_abort({0x23, 0x10, 0x10, 0x01, 'S', 'A', 'V', 'E'}, 0x1010, 1, kAbortStore);
  h.expect_abort({0x23, 0x11, 0x10, 0x01, 'l', 'o', 'a', 'd'}, 0x1011, 1, kAbortStore);
  h.expect_abort({0x23, 0x11, 0x10, 0x01, 's', 'a', 'v', 'e'}, 0x1011, 1, kAbortStore);
}

// ---- 08000021h local control ----------------------------------------------------------------
TEST_F(SdoAbort, OutputsUnderLocalControl_08000021) {
  operational();
  ASSERT_EQ(h.write_u8(0x2100, 0, 1), 0u);
  h.expect_abort({0x2F, 0x00, 0x62, 0x01, 0x55, 0, 0, 0}, 0x6200, 1, kAbortLocalControl);
  h.expect_abort({0x2F, 0x00, 0x62, 0x02, 0x55, 0, 0, 0}, 0x6200, 2, kAbortLocalControl);
  ASSERT_EQ(h.write_u8(0x2100, 0, 0), 0u);
  EXPECT_EQ(h.write_u8(0x6200, 1, 0x55), 0u);
  EXPECT_EQ(io.output(0), 0x55);
}

// ---- 08000022h present device state --------------------------------------------------------
TEST_F(SdoAbort, DeviceState_08000022) {
  ASSERT_EQ(h.write_u32(0x1006, 0, 10000), 0u);
  h.expect_abort({0x2F, 0x19, 0x10, 0x00, 5, 0, 0, 0}, 0x1019, 0, kAbortDeviceState);
  // Outputs follow the network only while operational.
  h.expect_abort({0x2F, 0x00, 0x62, 0x01, 0x01, 0, 0, 0}, 0x6200, 1, kAbortDeviceState);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
