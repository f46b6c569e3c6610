// The one register map (gateway/register_map.h), black box: where an OD entry
// sits in each Modbus table and how many addresses it takes. The register
// bank, mb2co-plant's layout, mb2co-od's register-map page and the
// simulator's PCs all locate the station's registers through it.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "canopen/od.h"
#include "gateway/od_register_bank.h"
#include "gateway/register_map.h"

namespace mb2co {
namespace {

using canopen::OdKey;
using gateway::MapItem;
using modbus::Table;
namespace e = gateway::od::GatewayEntry;

constexpr uint32_t map_entry(uint16_t index, uint8_t sub, uint8_t bits) {
  return OdKey{index, sub, bits}.map_entry();
}

class MapLayout : public ::testing::Test {
 protected:
  gateway::od::GatewayValues values{};
  canopen::ObjectDictionary od{gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values)};

  void SetUp() override { od.restore_defaults(0x0000, 0xFFFF); }
  /// Replaces a table's map by `entries` (sub 1..n), without the bank's checks.
  void set_map(Table table, const std::vector<uint32_t>& entries) {
    const uint16_t row0 = od.find(gateway::map_index(table), 0);
    od.set(row0, static_cast<uint32_t>(entries.size()));
    for (size_t k = 0; k < entries.size(); ++k) od.set(static_cast<uint16_t>(row0 + 1 + k), entries[k]);
  }
};

TEST(MapLayoutRules, TheMapOfEachTable) {
  EXPECT_EQ(gateway::map_index(Table::kHoldingRegisters), 0x2400);
  EXPECT_EQ(gateway::map_index(Table::kInputRegisters), 0x2401);
  EXPECT_EQ(gateway::map_index(Table::kCoils), 0x2402);
  EXPECT_EQ(gateway::map_index(Table::kDiscreteInputs), 0x2403);
  EXPECT_FALSE(gateway::is_map_index(0x23FF));
  EXPECT_TRUE(gateway::is_map_index(0x2400));
  EXPECT_TRUE(gateway::is_map_index(0x2403));
  EXPECT_FALSE(gateway::is_map_index(0x2404));
  EXPECT_EQ(gateway::map_capacity(Table::kInputRegisters), gateway::kInputMapSize);
  EXPECT_EQ(gateway::map_capacity(Table::kCoils), gateway::kCoilMapSize);
}

// Every length a mapped row can have: BOOL .. UNSIGNED64, and a string of n
// bytes mapped whole (16 bits per 2 characters).
TEST(MapLayoutRules, WidthOfEveryRowType) {
  struct Case {
    uint8_t bits;
    uint8_t registers;
  } cases[] = {{1, 1},  {8, 1},  {16, 1}, {24, 2}, {32, 2},
               {40, 3}, {48, 3}, {56, 4}, {64, 4}, {16 * 7, 7}};  // a VISIBLE_STRING of 13 characters
  for (const Case& c : cases) {
    SCOPED_TRACE(static_cast<int>(c.bits));
    EXPECT_EQ(gateway::entry_width(map_entry(0x2000, 1, c.bits), false), c.registers);
    // In a bit table every entry is one address.
    EXPECT_EQ(gateway::entry_width(map_entry(0x2000, 1, c.bits), true), 1);
  }
  // An unmapped address (entry 0) is one address in every table.
  EXPECT_EQ(gateway::entry_width(0, false), 1);
  EXPECT_EQ(gateway::entry_width(0, true), 1);
}

TEST_F(MapLayout, EntryToFirstRegisterAndWidthForEveryRowType) {
  const OdKey name = e::x1008_0_deviceName;  // VISIBLE_STRING, a register run
  const uint8_t name_bits = static_cast<uint8_t>(16u * ((od.capacity_of(od.find(name)) + 1u) / 2u));
  set_map(Table::kHoldingRegisters,
          {e::x2100_1_runCommand.map_entry(), e::x2000_2_bitrateKbit.map_entry(),
           e::x1006_0_communicationCyclePeriod.map_entry(), e::x2500_1_measuredValue.map_entry(), 0,
           e::x2500_2_eventCounter.map_entry(), map_entry(name.index, name.sub, name_bits)});
  struct Want {
    OdKey key;
    uint16_t first;
    uint8_t width;
  } wants[] = {{e::x2100_1_runCommand, 0, 1},
               {e::x2000_2_bitrateKbit, 1, 1},
               {e::x1006_0_communicationCyclePeriod, 2, 2},
               {e::x2500_1_measuredValue, 4, 2},
               {e::x2500_2_eventCounter, 7, 4},
               {OdKey{name.index, name.sub, name_bits}, 11, 7}};
  for (const Want& w : wants) {
    SCOPED_TRACE(testing::Message() << std::hex << w.key.index << "/" << static_cast<int>(w.key.sub));
    const MapItem item = gateway::locate(od, Table::kHoldingRegisters, w.key);
    ASSERT_TRUE(item.mapped());
    EXPECT_EQ(item.first, w.first);
    EXPECT_EQ(item.width, w.width);
  }
}

TEST_F(MapLayout, TheBankServesAnEntryWhereTheMapLocatesIt) {
  set_map(Table::kInputRegisters, {0, e::x2100_3_stop2Count.map_entry(), e::x2300_1_buttonEdgeUs.map_entry(),
                                   e::x2500_2_eventCounter.map_entry()});
  od.set(od.find(e::x2100_3_stop2Count), 0x1234);
  od.set(od.find(e::x2300_1_buttonEdgeUs), 0x89ABCDEF);
  uint8_t counter[8] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08};
  std::memcpy(od.ram(od.find(e::x2500_2_eventCounter)), counter, sizeof counter);
  gateway::OdRegisterBank bank(od);
  auto read = [&](OdKey key) {
    const MapItem item = gateway::locate(od, Table::kInputRegisters, key);
    EXPECT_TRUE(item.mapped());
    std::vector<uint8_t> bytes(2u * item.width);
    EXPECT_EQ(bank.read_registers(Table::kInputRegisters, item.first, {bytes.data(), item.width}),
              modbus::Exception::kNone);
    return bytes;
  };
  EXPECT_EQ(read(e::x2100_3_stop2Count), (std::vector<uint8_t>{0x12, 0x34}));
  EXPECT_EQ(read(e::x2300_1_buttonEdgeUs), (std::vector<uint8_t>{0x89, 0xAB, 0xCD, 0xEF}));
  EXPECT_EQ(read(e::x2500_2_eventCounter),
            (std::vector<uint8_t>{0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01}));
}

// The windows: items back to back from address 0, in sub-index order.
TEST_F(MapLayout, WindowsLieBackToBackFromAddressZero) {
  for (Table table :
       {Table::kHoldingRegisters, Table::kInputRegisters, Table::kCoils, Table::kDiscreteInputs}) {
    gateway::MapWalk<gateway::OdMapEntries> walk(gateway::OdMapEntries(od, table),
                                                 gateway::is_bit_table(table));
    uint16_t end = 0;
    uint8_t sub = 0;
    while (walk.next()) {
      EXPECT_EQ(walk.item().sub, ++sub);
      EXPECT_EQ(walk.item().first, end);
      end = static_cast<uint16_t>(end + walk.item().width);
    }
    EXPECT_EQ(sub, od.get(od.find(gateway::map_index(table), 0)));
  }
  // docs/register-map.md: 24 input registers (the last 2003h), 20 holding
  // registers on the host (14 on the Uno, without 2500h), 2 coils, 7 DIs.
  const MapItem last_ir = gateway::locate(od, Table::kInputRegisters, e::x2003_0_storageDamageCount);
  EXPECT_EQ(last_ir.first + last_ir.width, 24);
  const MapItem counter = gateway::locate(od, Table::kHoldingRegisters, e::x2500_2_eventCounter);
  EXPECT_EQ(counter.first + counter.width, 20);
}

TEST_F(MapLayout, AHoleMovesEverythingAfterIt) {
  set_map(Table::kInputRegisters, {0, 0, e::x2100_2_runState.map_entry()});
  const MapItem item = gateway::locate(od, Table::kInputRegisters, e::x2100_2_runState);
  EXPECT_EQ(item.first, 2);
  EXPECT_EQ(item.sub, 3);
}

TEST_F(MapLayout, BitTablesLocateBitZeroOfAnEntry) {
  // Coil 1 is the lab LED output 6200h/1 (8 bits, mapped as one bit).
  EXPECT_EQ(gateway::locate(od, Table::kCoils, e::x6200_1_writeOutput8Bit1).first, 1);
  EXPECT_EQ(gateway::locate(od, Table::kDiscreteInputs, e::x2140_1_startPressed).first, 0);
}

TEST_F(MapLayout, AnUnknownOrNarrowerEntryIsNotLocated) {
  EXPECT_FALSE(gateway::locate(od, Table::kInputRegisters, OdKey{0x2999, 0, 8}).mapped());
  // Mapped, but not in this table.
  EXPECT_FALSE(gateway::locate(od, Table::kHoldingRegisters, e::x6000_1_readInput8Bit1).mapped());
  // A 32-bit entry mapped as its low 16 bits is not its value.
  set_map(Table::kInputRegisters, {map_entry(0x2300, 1, 16)});
  EXPECT_FALSE(gateway::locate(od, Table::kInputRegisters, e::x2300_1_buttonEdgeUs).mapped());
  EXPECT_EQ(gateway::default_address(Table::kInputRegisters, OdKey{0x2999, 0, 8}), 0xFFFF);
}

TEST_F(MapLayout, CountBeyondTheCapacityIsCut) {
  od.set(od.find(0x2402, 0), 200);
  gateway::MapWalk<gateway::OdMapEntries> walk(gateway::OdMapEntries(od, Table::kCoils), true);
  int items = 0;
  while (walk.next()) ++items;
  EXPECT_EQ(items, gateway::kCoilMapSize);
}

// The compile-time default map (the simulator's PCs, tests) and the OD's
// default map locate every entry of every table alike.
TEST_F(MapLayout, DefaultLocationsAreTheDefaultOdsLocations) {
  static_assert(gateway::default_address(Table::kInputRegisters, e::x6000_1_readInput8Bit1) == 0, "IR 0");
  for (Table table :
       {Table::kHoldingRegisters, Table::kInputRegisters, Table::kCoils, Table::kDiscreteInputs}) {
    gateway::MapWalk<gateway::OdMapEntries> walk(gateway::OdMapEntries(od, table),
                                                 gateway::is_bit_table(table));
    while (walk.next()) {
      const uint32_t entry = walk.item().entry;
      if (entry == 0) continue;
      const uint16_t row = od.find(canopen::map_index(entry), canopen::map_sub(entry));
      const OdKey key{canopen::map_index(entry), canopen::map_sub(entry),
                      static_cast<uint8_t>(gateway::is_bit_table(table) ? 8u * od.size_of(row)
                                                                        : canopen::map_bits(entry))};
      const MapItem at_compile_time = gateway::default_location(table, key);
      const MapItem in_od = gateway::locate(od, table, key);
      EXPECT_EQ(at_compile_time.first, in_od.first);
      EXPECT_EQ(at_compile_time.width, in_od.width);
      EXPECT_EQ(at_compile_time.sub, walk.item().sub);
    }
  }
}

}  // namespace
}  // namespace mb2co
