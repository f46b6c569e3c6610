// Every row of an OD reads as its list line says, whatever the OD keeps in
// flash (the PDO records as one template per kind: od_define.h): index,
// sub-index, type, attributes and hook from every accessor, each key finds
// its own row, and a RAM row's value is its named member of the value block.
// Black box over ObjectDictionary, against the X-macro list itself.
//
// Use: define MB2CO_LISTED_VALUES to the OD's value-block type, then
//   const test::ListedRow kRows[] = {LIST(MB2CO_LISTED_N, MB2CO_LISTED_S)};
//   test::expect_rows_as_listed(od, kRows, count, values);
#pragma once
#include <gtest/gtest.h>
#include <stddef.h>
#include <stdint.h>

#include "canopen/od.h"

namespace mb2co {
namespace test {

/// One list line as the OD must hand it out.
struct ListedRow {
  uint16_t index;
  uint8_t sub;
  uint8_t type;
  uint8_t attr;
  uint8_t hook;
  ptrdiff_t value_offset;  ///< in the value block; -1 for a CONST row (no value there)
};

// clang-format off
#define MB2CO_LISTED_AT_CONST(id) (-1)
#define MB2CO_LISTED_AT_RO(id) static_cast<ptrdiff_t>(offsetof(MB2CO_LISTED_VALUES, id))
#define MB2CO_LISTED_AT_WO MB2CO_LISTED_AT_RO
#define MB2CO_LISTED_AT_RW MB2CO_LISTED_AT_RO
#define MB2CO_LISTED_N(index, sub, id, type, access, flags, hook, def, name)                          \
  {index, sub, MB2CO_OD_DT_##type, static_cast<uint8_t>(MB2CO_OD_ACC_##access | (flags)), hook,    \
   MB2CO_LISTED_AT_##access(id)},
#define MB2CO_LISTED_S(index, sub, id, access, hook, cap, text, name)                                 \
  {index, sub, static_cast<uint8_t>(MB2CO_OD_CAP_TYPE(cap)),                                        \
   static_cast<uint8_t>(MB2CO_OD_ACC_##access | ::mb2co::canopen::kAttrString), hook,               \
   MB2CO_LISTED_AT_##access(id)},
// clang-format on

inline void expect_rows_as_listed(const canopen::ObjectDictionary& od, const ListedRow* rows, size_t count,
                                  const uint8_t* values) {
  ASSERT_EQ(od.row_count(), count);
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const ListedRow& l = rows[r];
    SCOPED_TRACE(testing::Message() << std::hex << "row of " << l.index << "/" << +l.sub);
    const canopen::OdEntry e = od.entry(r);
    EXPECT_EQ(e.index, l.index);
    EXPECT_EQ(e.sub, l.sub);
    EXPECT_EQ(e.data_type(), l.type);
    EXPECT_EQ(e.attr, l.attr);
    EXPECT_EQ(e.hook, l.hook);
    EXPECT_EQ(od.index_of(r), l.index);
    EXPECT_EQ(od.sub_of(r), l.sub);
    EXPECT_EQ(od.type_of(r), l.type);
    EXPECT_EQ(od.attr(r), l.attr);
    EXPECT_EQ(od.hook_of(r), l.hook);
    EXPECT_EQ(od.find(l.index, l.sub), r);
    // Every index begins with its sub 0: the first row of its index.
    EXPECT_EQ(od.first_row(l.index), l.sub == 0 ? r : od.find(l.index, 0));
    EXPECT_TRUE(od.has_index(l.index));
    if (l.value_offset >= 0) {
      EXPECT_EQ(od.ram(r), values + l.value_offset);
      EXPECT_EQ(e.loc, l.value_offset);
    } else {
      EXPECT_EQ(od.ram(r), nullptr);
    }
  }
}

}  // namespace test
}  // namespace mb2co
