// Every CiA 301 basic data type in the OD core, on a test-only OD with one
// entry of each: sizes, SDO upload and download (expedited up to 4 bytes,
// segmented above), length and range aborts, REAL limits compared as the
// reals are ordered, the data-type entries 0001h-001Bh, and PDO mapping of
// the 24/40/48/56-bit lengths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "canopen/pdo_map.h"
#include "ionode/io_node_od.h"
#include "od_rows_check.h"
#include "test_fixture.h"
#include "types_od.h"
#include "value_bytes.h"

namespace mb2co {
namespace test {

namespace {

using namespace canopen;

/// Node id 5 on the all-types OD, pre-operational, log empty.
class OdTypes : public ::testing::Test {
 protected:
  static constexpr uint8_t kId = 5;
  void SetUp() override {
    node.start(kId, h.now);
    bus.frames.clear();
  }
  uint16_t row(uint16_t index) { return od.find(index, 0); }
  /// The first SDO answer to an upload request (expedited or the segmented
  /// initiate), the transfer then left to be replaced by the next request.
  CanFrame upload_initiate(uint16_t index) {
    return h.sdo({0x40, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), 0});
  }
  FrameLog bus;
  types::od::TypesValues values{};
  ObjectDictionary od{types::od::TypesDefinition, reinterpret_cast<uint8_t*>(&values)};
  Node node{od, bus.sink()};
  Harness h{node, bus};
};

struct TypeCase {
  uint16_t index;
  DataType type;
  uint8_t bytes;
};
// The numeric entries 2101h-2115h and their sizes (CiA 301 §7.1).
const TypeCase kNumeric[] = {
    {0x2101, kBoolean, 1},       {0x2102, kInteger8, 1},   {0x2103, kInteger16, 2},  {0x2104, kInteger24, 3},
    {0x2105, kInteger32, 4},     {0x2106, kInteger40, 5},  {0x2107, kInteger48, 6},  {0x2108, kInteger56, 7},
    {0x2109, kInteger64, 8},     {0x210A, kUnsigned8, 1},  {0x210B, kUnsigned16, 2}, {0x210C, kUnsigned24, 3},
    {0x210D, kUnsigned32, 4},    {0x210E, kUnsigned40, 5}, {0x210F, kUnsigned48, 6}, {0x2110, kUnsigned56, 7},
    {0x2111, kUnsigned64, 8},    {0x2112, kReal32, 4},     {0x2113, kReal64, 8},     {0x2114, kTimeOfDay, 6},
    {0x2115, kTimeDifference, 6}};

TEST_F(OdTypes, EveryTypeHasItsSizeAndGoesExpeditedUpToFourBytesSegmentedAbove) {
  for (const TypeCase& t : kNumeric) {
    SCOPED_TRACE(::testing::Message() << std::hex << t.index);
    const uint16_t r = row(t.index);
    ASSERT_TRUE(r != ObjectDictionary::kNoRow);
    EXPECT_EQ(od.type_of(r), t.type);
    EXPECT_EQ(od.size_of(r), t.bytes);
    const CanFrame f = upload_initiate(t.index);
    if (t.bytes <= 4) {
      // expedited: four bytes without size indication (seed 004 §2.11), fewer with 4 - n in bits 2-3
      EXPECT_EQ(f.data[0], t.bytes == 4 ? 0x42 : 0x43 | ((4 - t.bytes) << 2)) << to_string(f);
    } else {
      EXPECT_EQ(f.data[0], 0x41) << to_string(f);  // segmented, size indicated
      EXPECT_EQ(le32(&f.data[4]), t.bytes);
    }
  }
}

TEST_F(OdTypes, EveryNumericTypeReadsBackWhatWasWrittenBySdo) {
  for (const TypeCase& t : kNumeric) {
    SCOPED_TRACE(::testing::Message() << std::hex << t.index);
    // A value that uses every byte (BOOLEAN: 1), below each type's top bit.
    Bytes v(t.bytes);
    for (uint8_t i = 0; i < t.bytes; ++i) v[i] = static_cast<uint8_t>(0x11 * (i + 1));
    if (t.type == kBoolean) v[0] = 1;
    EXPECT_EQ(h.download(t.index, 0, v), 0u);
    Bytes back;
    ASSERT_EQ(h.upload(t.index, 0, &back), 0u);
    EXPECT_EQ(back, v);
    EXPECT_EQ(0, std::memcmp(od.ram(row(t.index)), v.data(), v.size()));
  }
}

TEST_F(OdTypes, DefaultsOfTheNewTypes) {
  Bytes b;
  ASSERT_EQ(h.upload(0x2112, 0, &b), 0u);
  EXPECT_EQ(b, le_bytes(bits_of(-1234.5625f), 4)) << "REAL32 default: the float's IEEE bits";
  EXPECT_EQ(float{values.x2112_0_real32}, -1234.5625f);
  ASSERT_EQ(h.upload(0x2104, 0, &b), 0u);
  EXPECT_EQ(b, le_bytes(0x123456, 3));
  ASSERT_EQ(h.upload(0x2111, 0, &b), 0u);
  EXPECT_EQ(b, le_bytes(0xDEADBEEF, 8)) << "a wide default: its 32 bits, zeros above";
  ASSERT_EQ(h.upload(0x2121, 0, &b), 0u);
  EXPECT_EQ(b, (Bytes{1, 2, 3, 0, 0, 0})) << "an OCTET_STRING is always its whole capacity";
}

TEST_F(OdTypes, ConstantsOfTheFloatBits) {
  for (const float f :
       {-1234.5625f, 1.0f, 0.1f, 3.4028235e38f, 1.17549435e-38f, 1.0e-45f, 2.5e-40f, -7.25e-39f}) {
    EXPECT_EQ(od_real32_bits(f), bits_of(f)) << f;
  }
}

TEST_F(OdTypes, RealLimitKeysOrderAsTheRealsDo) {
  const float inf = std::numeric_limits<float>::infinity();
  const float values_f[] = {-inf,  -3.4e38f, -1234.5625f, -1.0f,    -1.0e-45f,
                            -0.0f, 0.0f,     1.0e-45f,    2.5e-40f, 1.17549435e-38f,
                            0.1f,  1.0f,     1234.5625f,  3.4e38f,  inf};
  for (const float a : values_f) {
    for (const float b : values_f) {
      const OdLimitValue ka = od_real_limit(bits_of(a), 4);
      const OdLimitValue kb = od_real_limit(bits_of(b), 4);
      EXPECT_EQ(ka < kb, a < b) << a << " " << b;
      EXPECT_EQ(ka == kb, a == b) << a << " " << b;
    }
  }
  const double values_d[] = {-1.0e300, -100.5, -5e-324, -0.0, 0.0, 5e-324, 99.5, 100.0, 1.0e300};
  for (const double a : values_d) {
    for (const double b : values_d) {
      EXPECT_EQ(od_real_limit(bits_of(a), 8) < od_real_limit(bits_of(b), 8), a < b) << a << " " << b;
    }
  }
  EXPECT_EQ(od_real_limit_bits(od_real32_limit(-1.5f), 4), bits_of(-1.5f));
}

TEST_F(OdTypes, LengthsThatDoNotMatchTheTypeAreRefused) {
  // Expedited, size indicated: 2 bytes to a REAL32, 4 to an UNSIGNED64 (too short).
  h.expect_abort({0x2B, 0x12, 0x21, 0x00, 0x00, 0x00, 0, 0}, 0x2112, 0, kAbortTooShort);
  h.expect_abort({0x23, 0x11, 0x21, 0x00, 1, 2, 3, 4}, 0x2111, 0, kAbortTooShort);
  // 4 bytes to an INTEGER24: too long.
  h.expect_abort({0x23, 0x04, 0x21, 0x00, 1, 2, 3, 4}, 0x2104, 0, kAbortTooLong);
  // Segmented: 9 bytes announced to a 64-bit entry (too long), 5 to a 48-bit one (too short).
  h.expect_abort({0x21, 0x09, 0x21, 0x00, 9, 0, 0, 0}, 0x2109, 0, kAbortTooLong);
  h.expect_abort({0x21, 0x0F, 0x21, 0x00, 5, 0, 0, 0}, 0x210F, 0, kAbortTooShort);
  EXPECT_EQ(h.download_segmented(0x2107, 0, Bytes(5, 0x22), false), kAbortTooShort);
  // 6 bytes announced, 7 sent: the data does not match its own size (06070010h).
  const CanFrame init = h.sdo({0x21, 0x0F, 0x21, 0x00, 6, 0, 0, 0});
  ASSERT_EQ(init.data[0], 0x60);
  const CanFrame seg = h.sdo({0x01, 1, 2, 3, 4, 5, 6, 7});
  EXPECT_EQ(to_string(seg), abort_frame(kId, 0x210F, 0, kAbortTypeMismatch));
  // OCTET_STRING and DOMAIN have their fixed length; a VISIBLE_STRING may be shorter.
  EXPECT_EQ(h.download(0x2121, 0, Bytes{1, 2, 3}), kAbortTooShort);
  EXPECT_EQ(h.download(0x2121, 0, Bytes{9, 0, 8, 0, 7, 0}), 0u);
  EXPECT_EQ(h.download(0x2123, 0, Bytes(11, 0x55)), kAbortTooShort);
  EXPECT_EQ(h.download(0x2123, 0, Bytes(13, 0x55)), kAbortTooLong);
  EXPECT_EQ(h.download(0x2120, 0, bytes_of("abc")), 0u);
  EXPECT_EQ(h.read_string(0x2120, 0), "abc");
  EXPECT_EQ(h.download(0x2122, 0, Bytes{'A', 0, 'B', 0, 'C', 0, 'D', 0}), 0u);
}

TEST_F(OdTypes, StringsGoAtTheirLength) {
  Bytes b;
  ASSERT_EQ(h.upload(0x2120, 0, &b), 0u);
  EXPECT_EQ(b, bytes_of("hello"));
  const CanFrame f = upload_initiate(0x2121);
  EXPECT_EQ(f.data[0], 0x41) << "six octets: segmented";
  EXPECT_EQ(le32(&f.data[4]), 6u);
  EXPECT_EQ(h.download(0x2123, 0, Bytes(12, 0xA5)), 0u);
  ASSERT_EQ(h.upload(0x2123, 0, &b), 0u);
  EXPECT_EQ(b, Bytes(12, 0xA5));
  ASSERT_EQ(h.upload(0x2122, 0, &b), 0u);
  EXPECT_EQ(b.size(), 8u) << "UNICODE_STRING(4): 8 bytes";
}

TEST_F(OdTypes, BooleanIsZeroOrOne) {
  EXPECT_EQ(h.download(0x2101, 0, Bytes{0}), 0u);
  h.expect_abort({0x2F, 0x01, 0x21, 0x00, 2, 0, 0, 0}, 0x2101, 0, kAbortInvalidValue);
}

TEST_F(OdTypes, IntegerLimitsOfEveryWidth) {
  EXPECT_EQ(h.download(0x2200, 0, le_bytes(1000, 3)), 0u);
  EXPECT_EQ(h.download(0x2200, 0, le_bytes(static_cast<uint64_t>(-1000), 3)), 0u);
  EXPECT_EQ(h.download(0x2200, 0, le_bytes(1001, 3)), kAbortValueTooHigh);
  EXPECT_EQ(h.download(0x2200, 0, le_bytes(static_cast<uint64_t>(-1001), 3)), kAbortValueTooLow);
  EXPECT_EQ(h.download(0x2201, 0, le_bytes(9, 5)), kAbortValueTooLow);
  EXPECT_EQ(h.download(0x2201, 0, le_bytes(0x10000000000ULL - 1000, 5)), 0u);
  EXPECT_EQ(h.download(0x2201, 0, le_bytes(0x10000000000ULL - 999, 5)), kAbortValueTooHigh);
  EXPECT_EQ(h.download(0x2202, 0, le_bytes(static_cast<uint64_t>(-5000000000000LL), 8)), 0u);
  EXPECT_EQ(h.download(0x2202, 0, le_bytes(static_cast<uint64_t>(-5000000000001LL), 8)), kAbortValueTooLow);
  EXPECT_EQ(h.download(0x2202, 0, le_bytes(5000000000001ULL, 8)), kAbortValueTooHigh);
  EXPECT_EQ(h.download(0x2203, 0, le_bytes(1000000000000000ULL, 8)), 0u);
  EXPECT_EQ(h.download(0x2203, 0, le_bytes(1000000000000001ULL, 8)), kAbortValueTooHigh);
  // Above INT64_MAX: above every limit, not a negative number.
  EXPECT_EQ(h.download(0x2203, 0, le_bytes(0xFFFFFFFFFFFFFFF0ULL, 8)), kAbortValueTooHigh);
  EXPECT_EQ(h.download(0x2203, 0, le_bytes(9, 8)), kAbortValueTooLow);
  EXPECT_EQ(h.download(0x2206, 0, le_bytes(0xFFFFFFFFFFFFFFULL, 7)), kAbortValueTooHigh);
  EXPECT_EQ(h.download(0x2206, 0, le_bytes(0xFFFFFFFFFFFFFEULL, 7)), 0u);
  Bytes b;
  ASSERT_EQ(h.upload(0x2203, 0, &b), 0u);
  EXPECT_EQ(b, le_bytes(1000000000000000ULL, 8)) << "refused writes left the last value";
}

TEST_F(OdTypes, RealLimitsCompareAsReals) {
  const auto real32 = [&](float f) { return h.download(0x2204, 0, le_bytes(bits_of(f), 4)); };
  EXPECT_EQ(real32(2.5f), 0u);
  EXPECT_EQ(real32(-1.5f), 0u);
  EXPECT_EQ(real32(-0.0f), 0u);
  EXPECT_EQ(real32(1.0e-45f), 0u) << "subnormal";
  EXPECT_EQ(real32(-1.0e-45f), 0u) << "negative subnormal";
  EXPECT_EQ(real32(2.5000002f), kAbortValueTooHigh);
  EXPECT_EQ(real32(-1.5000001f), kAbortValueTooLow);
  EXPECT_EQ(real32(-1.0e30f), kAbortValueTooLow);
  EXPECT_EQ(real32(std::numeric_limits<float>::infinity()), kAbortValueTooHigh);
  EXPECT_EQ(real32(-std::numeric_limits<float>::infinity()), kAbortValueTooLow);
  EXPECT_EQ(real32(std::nanf("")), kAbortValueTooHigh) << "a NaN is in no range";
  const auto real64 = [&](double d) { return h.download(0x2205, 0, le_bytes(bits_of(d), 8)); };
  EXPECT_EQ(real64(99.5), 0u);
  EXPECT_EQ(real64(-100.0), 0u);
  EXPECT_EQ(real64(100.0000001), kAbortValueTooHigh);
  EXPECT_EQ(real64(-100.5), kAbortValueTooLow);
  EXPECT_EQ(real64(4.9e-324), 0u);
}

TEST_F(OdTypes, DataTypeEntriesGiveTheBitLengths) {
  const struct {
    uint16_t index;
    uint32_t bits;
  } kTypes[] = {{0x01, 1},  {0x02, 8},  {0x03, 16}, {0x04, 32}, {0x05, 8},  {0x06, 16}, {0x07, 32},
                {0x08, 32}, {0x09, 8},  {0x0A, 8},  {0x0B, 16}, {0x0C, 48}, {0x0D, 48}, {0x0F, 8},
                {0x10, 24}, {0x11, 64}, {0x12, 40}, {0x13, 48}, {0x14, 56}, {0x15, 64}, {0x16, 24},
                {0x18, 40}, {0x19, 48}, {0x1A, 56}, {0x1B, 64}};
  for (const auto& t : kTypes) {
    Bytes b;
    ASSERT_EQ(h.upload(t.index, 0, &b), 0u) << std::hex << t.index;
    EXPECT_EQ(b, le_bytes(t.bits, 4)) << "UNSIGNED32 bit length of " << std::hex << t.index;
  }
  // 000Eh and 0017h are reserved: no such object.
  h.expect_abort({0x40, 0x0E, 0x00, 0x00}, 0x000E, 0, kAbortNoObject);
  h.expect_abort({0x40, 0x17, 0x00, 0x00}, 0x0017, 0, kAbortNoObject);
}

TEST_F(OdTypes, TransmitMappingOf24And40BitsAnd48And8AndOf56Bits) {
  ASSERT_EQ(h.download(0x2104, 0, Bytes{0x01, 0x02, 0x83}), 0u);              // INTEGER24
  ASSERT_EQ(h.download(0x210E, 0, Bytes{0x11, 0x12, 0x13, 0x14, 0x15}), 0u);  // UNSIGNED40
  h.map_pdo(0x1800, {0x21040018, 0x210E0028});                                // 24 + 40 = 64 bits
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<185> 01 02 83 11 12 13 14 15"}));
  h.nmt(0x80, kId);
  ASSERT_EQ(h.download(0x2107, 0, Bytes{0xA1, 0xA2, 0xA3, 0xA4, 0xA5, 0xA6}), 0u);  // INTEGER48
  ASSERT_EQ(h.download(0x2110, 0, Bytes{0xB1, 0xB2, 0xB3, 0xB4, 0xB5, 0xB6, 0xB7}), 0u);
  h.map_pdo(0x1800, {0x21070030, 0x210A0008});  // 48 + 8
  h.nmt(0x01, kId);
  h.take();
  ASSERT_EQ(h.download(0x210A, 0, Bytes{0x5A}), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<185> A1 A2 A3 A4 A5 A6 5A"}));
  h.nmt(0x80, kId);
  h.map_pdo(0x1800, {0x21100038});  // UNSIGNED56 alone: 7 bytes
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<185> B1 B2 B3 B4 B5 B6 B7"}));
}

TEST_F(OdTypes, ReceiveMappingOf24And40AndOf56Bits) {
  h.map_pdo(0x1400, {0x210C0018, 0x21060028});  // UNSIGNED24 + INTEGER40
  h.nmt(0x01, kId);
  h.take();
  h.rx(F(0x205, {0x01, 0x02, 0x03, 0xF1, 0xF2, 0xF3, 0xF4, 0xF5}));
  Bytes b;
  ASSERT_EQ(h.upload(0x210C, 0, &b), 0u);
  EXPECT_EQ(b, (Bytes{0x01, 0x02, 0x03}));
  ASSERT_EQ(h.upload(0x2106, 0, &b), 0u);
  EXPECT_EQ(b, (Bytes{0xF1, 0xF2, 0xF3, 0xF4, 0xF5}));
  h.nmt(0x80, kId);
  h.map_pdo(0x1400, {0x21080038});  // INTEGER56
  h.nmt(0x01, kId);
  h.rx(F(0x205, {0x71, 0x72, 0x73, 0x74, 0x75, 0x76, 0x77}));
  ASSERT_EQ(h.upload(0x2108, 0, &b), 0u);
  EXPECT_EQ(b, (Bytes{0x71, 0x72, 0x73, 0x74, 0x75, 0x76, 0x77}));
}

TEST_F(OdTypes, MappingLengthsBeyondTheEntryAreRefused) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000185u), 0u);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 0), 0u);
  // 56 bits of a 48-bit entry, 32 of a 24-bit one, 72 of a 64-bit one.
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x38, 0x00, 0x07, 0x21}, 0x1A00, 1, kAbortNotMappable);
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x20, 0x00, 0x04, 0x21}, 0x1A00, 1, kAbortNotMappable);
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x48, 0x00, 0x11, 0x21}, 0x1A00, 1, kAbortNotMappable);
  // Every mappable type at its own length.
  for (const TypeCase& t : kNumeric) {
    const uint32_t bits = t.type == kBoolean ? 1u : t.bytes * 8u;
    EXPECT_EQ(pdo_check_entry(od, (static_cast<uint32_t>(t.index) << 16) | bits, false), kSdoOk)
        << std::hex << t.index;
    EXPECT_EQ(pdo_check_entry(od, (static_cast<uint32_t>(t.index) << 16) | bits, true), kSdoOk)
        << std::hex << t.index;
  }
}

// get() of every numeric RAM row gives its value's bytes (little-endian, the
// low 4 of a wider one), whatever way it reads them: on hosts a direct
// table read as one masked 4-byte load (MB2CO_CONFIG_OD_DIRECT_GET), the
// last values of the block bytewise; on the Uno the row's decoding.
// Compared with copy_out(), which always decodes the row.

/// Fills the value block with distinct bytes, checks every row; returns
/// the end of the last numeric value and whether one lay within the
/// block's last 3 bytes (read bytewise).
uint16_t every_numeric_row_reads_its_bytes(const OdDefinition& def, uint8_t* values, bool* in_last_bytes) {
  for (uint16_t i = 0; i < def.values_size; ++i) values[i] = static_cast<uint8_t>(0x11 + 7 * i);
  const ObjectDictionary od(def, values);
  int checked = 0;
  uint16_t end = 0;
  *in_last_bytes = false;
  for (uint16_t row = 0; row < od.row_count(); ++row) {
    if ((od.attr(row) & (kAttrRam | kAttrString)) != kAttrRam) continue;
    uint8_t bytes[8] = {};
    const uint16_t n = od.copy_out(row, bytes, sizeof bytes);
    if (n == 0) continue;
    uint32_t expected = 0;
    memcpy(&expected, bytes, n < 4 ? n : 4);  // little-endian, as both targets
    EXPECT_EQ(od.get(row), expected) << "row " << row << ", " << n << " bytes";
    const uint16_t at = static_cast<uint16_t>(od.ram(row) - values);
    end = std::max(end, static_cast<uint16_t>(at + n));
    *in_last_bytes = *in_last_bytes || at + 4 > def.values_size;
    ++checked;
  }
  EXPECT_GT(checked, 10);
  return end;
}

/// As the OD is, and with the value block cut right after its last numeric
/// value; true when a value then lay within the last 3 bytes (read bytewise).
bool every_numeric_row_reads_its_bytes_also_at_the_block_end(const OdDefinition& def, uint8_t* values) {
  bool in_last_bytes = false;
  OdDefinition tight = def;
  tight.values_size = every_numeric_row_reads_its_bytes(def, values, &in_last_bytes);
  every_numeric_row_reads_its_bytes(tight, values, &in_last_bytes);
  return in_last_bytes;
}

TEST(OdGet, EveryNumericRowOfTheAllTypesOdReadsItsBytes) {
  types::od::TypesValues values{};
  ASSERT_EQ(sizeof values, types::od::TypesDefinition.values_size);
  every_numeric_row_reads_its_bytes_also_at_the_block_end(types::od::TypesDefinition,
                                                          reinterpret_cast<uint8_t*>(&values));
}

TEST(OdGet, EveryNumericRowOfTheIoNodeOdReadsItsBytes) {
  ionode::od::IoNodeValues values{};
  ASSERT_EQ(sizeof values, ionode::od::IoNodeDefinition.values_size);
  EXPECT_TRUE(every_numeric_row_reads_its_bytes_also_at_the_block_end(ionode::od::IoNodeDefinition,
                                                                      reinterpret_cast<uint8_t*>(&values)));
}

// The hosts' direct table and remembered find() answers on the all-types
// OD (test_od_direct.cpp has the I/O node's): every row as decoded, and a
// string's size, which the table does not keep, follows its text.
TEST(OdDirect, EveryRowOfTheAllTypesOdReadsAsItsRowSays) {
  types::od::TypesValues values{};
  const ObjectDictionary od(types::od::TypesDefinition, reinterpret_cast<uint8_t*>(&values));
  EXPECT_GT(every_row_reads_as_decoded(od), 20);
}

// A string's size is its text now (not in the table: size_of() decodes it),
// its capacity the row's.
TEST(OdDirect, AStringsSizeFollowsItsText) {
  types::od::TypesValues values{};
  ObjectDictionary od(types::od::TypesDefinition, reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  uint16_t row = kNoRow;
  for (uint16_t r = 0; r < od.row_count() && row == kNoRow; ++r) {
    if ((od.attr(r) & (kAttrRam | kAttrString | kAttrWrite)) == (kAttrRam | kAttrString | kAttrWrite) &&
        od.type_of(r) == kVisibleString && od.capacity_of(r) >= 3) {
      row = r;
    }
  }
  ASSERT_NE(row, kNoRow);
  const uint8_t one[1] = {'a'};
  ASSERT_EQ(od.write_row(row, one, 1), kSdoOk);
  EXPECT_EQ(od.size_of(row), 1u);
  const uint8_t three[3] = {'a', 'b', 'c'};
  ASSERT_EQ(od.write_row(row, three, 3), kSdoOk);
  EXPECT_EQ(od.size_of(row), 3u);
  EXPECT_GE(od.capacity_of(row), 3u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
