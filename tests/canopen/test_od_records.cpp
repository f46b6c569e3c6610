// The PDO communication and mapping records (1400h-1BFFh) kept as one
// template record per kind (od_define.h, OdRecordShape): the I/O node's OD
// (mapping records of 8 entries) reads row by row as its list says, and the
// compile-time checks refuse records that a template cannot stand for.
#include <gtest/gtest.h>

#include "canopen/od.h"
#include "canopen/od_comm.h"
#include "ionode/io_node_od.h"
#include "od_rows_as_listed.h"

namespace mb2co {
namespace {

using namespace canopen;  // the list's flags and hooks read unqualified
using ionode::od::IoNodeDefinition;
using ionode::od::IoNodeValues;

#define MB2CO_LISTED_VALUES IoNodeValues
const test::ListedRow kIoNodeRows[] = {MB2CO_IO_NODE_OD(MB2CO_LISTED_N, MB2CO_LISTED_S)};
#undef MB2CO_LISTED_VALUES

TEST(OdRecords, EveryRowOfTheIoNodeReadsAsItsListLine) {
  IoNodeValues values{};
  const ObjectDictionary od(IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  test::expect_rows_as_listed(od, kIoNodeRows, sizeof kIoNodeRows / sizeof kIoNodeRows[0],
                              reinterpret_cast<const uint8_t*>(&values));
}

TEST(OdRecords, TheRecordRowsFollowTheRowsBelow1400h) {
  size_t below = 0;
  for (const test::ListedRow& l : kIoNodeRows) below += l.index < 0x1400;
  EXPECT_EQ(IoNodeDefinition.record_first, below);
  EXPECT_EQ(IoNodeDefinition.record_count, 4u * (5u + 9u + 6u + 9u));
  const ObjectDictionary od(IoNodeDefinition, nullptr);
  EXPECT_EQ(od.find(0x1400, 0), IoNodeDefinition.record_first);
  EXPECT_EQ(od.index_of(static_cast<uint16_t>(IoNodeDefinition.record_first + 115u)), 0x1A03u);
  EXPECT_EQ(od.sub_of(static_cast<uint16_t>(IoNodeDefinition.record_first + 115u)), 8u);
}

// Indices between and beyond the records, and sub-indices a record lacks.
TEST(OdRecords, WhatNoRecordHasIsNotFound) {
  const ObjectDictionary od(IoNodeDefinition, nullptr);
  for (const uint16_t index : {uint16_t{0x1404}, uint16_t{0x15FF}, uint16_t{0x1604}, uint16_t{0x1804},
                               uint16_t{0x1A04}, uint16_t{0x1BFF}}) {
    EXPECT_EQ(od.find(index, 0), static_cast<uint16_t>(ObjectDictionary::kNoRow)) << std::hex << index;
    EXPECT_FALSE(od.has_index(index)) << std::hex << index;
  }
  EXPECT_EQ(od.find(0x1401, 4), static_cast<uint16_t>(ObjectDictionary::kNoRow));  // CiA 301's reserved sub 4
  EXPECT_EQ(od.find(0x1803, 7), static_cast<uint16_t>(ObjectDictionary::kNoRow));
  EXPECT_EQ(od.find(0x1A02, 9), static_cast<uint16_t>(ObjectDictionary::kNoRow));
  EXPECT_TRUE(od.has_index(0x1A03));
}

// Each PDO's record keeps its own defaults (the slots beside the template).
TEST(OdRecords, EveryRecordRestoresItsOwnDefaults) {
  IoNodeValues values{};
  ObjectDictionary od(IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  od.set_node_id(0x20);
  od.restore_defaults(0x1000, 0x1FFF);
  EXPECT_EQ(values.x1400_1_cobId, 0x220u);
  EXPECT_EQ(values.x1401_1_cobId, 0x80000320u);
  EXPECT_EQ(values.x1803_1_cobId, 0x800004A0u);
  EXPECT_EQ(values.x1600_0_mappedCount, 2u);
  EXPECT_EQ(values.x1601_0_mappedCount, 0u);
  EXPECT_EQ(values.x1A00_2_mappedObject2, 0x60000208u);
  EXPECT_EQ(od.default_value(od.find(0x1802, 1)), 0x800003A0u);
  EXPECT_EQ(od.entry(od.find(0x1A00, 1)).def, 0x60000108u);
  EXPECT_EQ(od.entry(od.find(0x1A01, 1)).def, 0u);
}

// Compile-time checks of od_define.h on hand-written rows (only the columns
// they read are set).
constexpr OdRow row_of(uint16_t index, uint8_t sub, uint8_t attr, uint8_t loc) {
  return OdRow{index, sub, kUnsigned8, kHookNone, attr, 0, loc, 0};
}
constexpr uint8_t kRw = kAttrRead | kAttrWrite | kAttrRam;

// 1400h-1403h, two rows each (sub 0 CONST, sub 1 a byte), values 3 bytes apart.
constexpr OdRow kUniform[] = {
    row_of(0x1000, 0, kRw, 0),        row_of(0x1400, 0, kAttrConst, 0), row_of(0x1400, 1, kRw, 1),
    row_of(0x1401, 0, kAttrConst, 0), row_of(0x1401, 1, kRw, 4),        row_of(0x1402, 0, kAttrConst, 0),
    row_of(0x1402, 1, kRw, 7),        row_of(0x1403, 0, kAttrConst, 0), row_of(0x1403, 1, kRw, 10),
    row_of(0x2000, 0, kRw, 13),
};
constexpr OdRecordShape kUniformShape = od_record_shape(kUniform, 10);
static_assert(kUniformShape.first == 1 && kUniformShape.count == 8 && kUniformShape.rows[0] == 2 &&
                  kUniformShape.rows[1] == 0 && kUniformShape.stride[0] == 3 && kUniformShape.base[3] == 8,
              "the shape of 4 records of 2 rows");
static_assert(od_records_uniform(kUniform, 10, kUniformShape), "4 records alike");
static_assert(od_rows_sorted(kUniform, 10), "sorted, each index from sub 0");

// The third record's value out of step.
constexpr OdRow kOutOfStep[] = {
    row_of(0x1400, 0, kAttrConst, 0), row_of(0x1400, 1, kRw, 1),        row_of(0x1401, 0, kAttrConst, 0),
    row_of(0x1401, 1, kRw, 4),        row_of(0x1402, 0, kAttrConst, 0), row_of(0x1402, 1, kRw, 8),
    row_of(0x1403, 0, kAttrConst, 0), row_of(0x1403, 1, kRw, 10),
};
static_assert(!od_records_uniform(kOutOfStep, 8, od_record_shape(kOutOfStep, 8)), "a value out of step");

// Attributes of its own in the second record (PDO-mappable).
constexpr OdRow kOtherAttr[] = {
    row_of(0x1400, 0, kAttrConst, 0),     row_of(0x1400, 1, kRw, 1),        row_of(0x1401, 0, kAttrConst, 0),
    row_of(0x1401, 1, kRw | kAttrPdo, 4), row_of(0x1402, 0, kAttrConst, 0), row_of(0x1402, 1, kRw, 7),
    row_of(0x1403, 0, kAttrConst, 0),     row_of(0x1403, 1, kRw, 10),
};
static_assert(!od_records_uniform(kOtherAttr, 8, od_record_shape(kOtherAttr, 8)), "attributes of its own");

// Three records only, and a fifth one.
constexpr OdRow kThree[] = {
    row_of(0x1400, 0, kAttrConst, 0),
    row_of(0x1401, 0, kAttrConst, 0),
    row_of(0x1402, 0, kAttrConst, 0),
    row_of(0x2000, 0, kRw, 0),
};
static_assert(!od_records_uniform(kThree, 4, od_record_shape(kThree, 4)), "three records of a kind");
constexpr OdRow kFive[] = {
    row_of(0x1400, 0, kAttrConst, 0), row_of(0x1401, 0, kAttrConst, 0), row_of(0x1402, 0, kAttrConst, 0),
    row_of(0x1403, 0, kAttrConst, 0), row_of(0x1404, 0, kAttrConst, 0),
};
static_assert(!od_records_uniform(kFive, 5, od_record_shape(kFive, 5)), "a fifth record");

// No records at all: nothing to check, every row a row of its own.
constexpr OdRow kNone[] = {row_of(0x1000, 0, kRw, 0), row_of(0x2000, 0, kRw, 1)};
static_assert(od_records_uniform(kNone, 2, od_record_shape(kNone, 2)) &&
                  od_record_shape(kNone, 2).count == 0 && od_record_shape(kNone, 2).first == 1,
              "an OD without PDOs");

// An index whose rows begin above sub 0.
constexpr OdRow kNoSub0[] = {row_of(0x1000, 0, kRw, 0), row_of(0x2000, 1, kRw, 1)};
static_assert(!od_rows_sorted(kNoSub0, 2), "every index begins with sub 0");

}  // namespace
}  // namespace mb2co
