// A check shared by the OD tests (test_od_direct.cpp, test_od_types.cpp):
// every row's single fields as its decoded row says.
#pragma once
#include <gtest/gtest.h>

#include "canopen/od.h"

namespace mb2co {
namespace test {

/// A copy EXPECT_EQ may take by reference (the class's has no definition).
constexpr uint16_t kNoRow = canopen::ObjectDictionary::kNoRow;

/// Every row's single fields agree with its decoded row (entry()), and
/// find() of its key answers the row, asked twice (searched, then
/// remembered). Returns the rows checked.
inline int every_row_reads_as_decoded(const canopen::ObjectDictionary& od) {
  int checked = 0;
  for (uint16_t row = 0; row < od.row_count(); ++row) {
    const canopen::OdEntry e = od.entry(row);
    EXPECT_EQ(od.index_of(row), e.index) << "row " << row;
    EXPECT_EQ(od.sub_of(row), e.sub) << "row " << row;
    EXPECT_EQ(od.attr(row), e.attr) << "row " << row;
    for (int ask = 0; ask < 2; ++ask) EXPECT_EQ(od.find(e.index, e.sub), row) << "row " << row;
    ++checked;
  }
  return checked;
}

}  // namespace test
}  // namespace mb2co
