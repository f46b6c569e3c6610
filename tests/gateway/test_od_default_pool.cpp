// The OD rows name their 32-bit default by a slot in a pool of the distinct
// defaults, or hold a small one themselves (OdRow::def_slot, built at compile
// time by MB2CO_OD_DEFINE): every row of the gateway's OD must still read the
// default its list line gives, and equal defaults must share one slot (the
// pool is what makes the rows small on the Uno).
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "canopen/od.h"
#include "gateway/gateway_od.h"

namespace mb2co {
namespace {

using namespace canopen;
using gateway::od::GatewayDefaults;
using gateway::od::GatewayDefinition;
using gateway::od::GatewayValues;

class OdDefaultPool : public ::testing::Test {
 protected:
  GatewayValues values{};
  ObjectDictionary od{GatewayDefinition, reinterpret_cast<uint8_t*>(&values)};
};

TEST_F(OdDefaultPool, EveryNumericRowReadsTheDefaultOfItsListLine) {
  size_t checked = 0;
  for (const OdDefault& d : GatewayDefaults) {
    const uint16_t row = od.find(d.index, d.sub);
    ASSERT_NE(row, static_cast<uint16_t>(ObjectDictionary::kNoRow));
    EXPECT_EQ(od.entry(row).def, d.value) << std::hex << d.index << "/" << +d.sub;
    ++checked;
  }
  // Strings are the rows without a numeric default.
  size_t strings = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) strings += (od.attr(r) & kAttrString) != 0;
  EXPECT_EQ(checked + strings, od.row_count());
}

TEST_F(OdDefaultPool, RestoredDefaultsAndConstantsReadAsTheList) {
  od.set_node_id(0);  // node-id-relative defaults read as written in the list
  od.restore_defaults(0x0000, 0xFFFF);
  for (const OdDefault& d : GatewayDefaults) {
    const uint16_t row = od.find(d.index, d.sub);
    const uint8_t bytes = static_cast<uint8_t>(od.size_of(row));
    const uint32_t mask = bytes >= 4 ? 0xFFFFFFFFu : (1u << (8 * bytes)) - 1u;
    EXPECT_EQ(od.get(row), d.value & mask) << std::hex << d.index << "/" << +d.sub;
  }
}

TEST_F(OdDefaultPool, SmallDefaultsInTheRowEqualLargeOnesShareOneSlot) {
  std::map<uint32_t, uint8_t> slot_of_value;
  std::map<uint8_t, uint32_t> value_of_slot;
  size_t literal = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint8_t slot = od.default_slot(r);  // a PDO record's row: its own, beside its template
    const uint32_t value = od.entry(r).def;
    if (value < kOdLiteralDefaults) {
      // In the row itself, marked by the top bit.
      EXPECT_EQ(slot, kOdLiteralDefaults | value) << std::hex << value;
      ++literal;
      continue;
    }
    ASSERT_EQ(slot & kOdLiteralDefaults, 0) << std::hex << value;
    EXPECT_EQ(GatewayDefinition.defaults[slot], value);
    const auto known = slot_of_value.emplace(value, slot);
    EXPECT_EQ(known.first->second, slot) << "two slots hold " << std::hex << value;
    value_of_slot.emplace(slot, value);
  }
  // Pool slots 0..n-1 are used, each by one distinct value: no unused or
  // duplicate pool entries.
  EXPECT_EQ(value_of_slot.size(), slot_of_value.size());
  EXPECT_EQ(value_of_slot.rbegin()->first + 1u, value_of_slot.size());
  EXPECT_LT(slot_of_value.size(), static_cast<size_t>(od.row_count()) / 2);
  EXPECT_GT(literal, 0u);
}

}  // namespace
}  // namespace mb2co
