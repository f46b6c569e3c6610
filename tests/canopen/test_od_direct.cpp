// What the hosts' direct table and remembered find() answers
// (MB2CO_CONFIG_OD_DIRECT_GET) keep is what the rows say, and every value
// read through them is the value stored now: black box against the OD's
// public API, on the I/O node's OD (PDO records, node-id-relative constants)
// (test_od_types.cpp: the all-types OD, every width and strings). On the
// Uno's profiles the same tests check the decoding they fall back to.
#include <gtest/gtest.h>

#include <cstring>

#include "canopen/od.h"
#include "ionode/io_node_od.h"
#include "od_rows_check.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

TEST(OdDirect, EveryRowOfTheIoNodeOdReadsAsItsRowSays) {
  ionode::od::IoNodeValues values{};
  const ObjectDictionary od(ionode::od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  EXPECT_GT(every_row_reads_as_decoded(od), 100);
}

// More keys than remembered slots (every row's, and an absent one beside
// each), asked in turn over and over: slots are shared (pigeonhole, whatever
// the hash), and each key still answers its own row or kNoRow, never the
// answer of the slot's previous key.
TEST(OdDirect, KeysSharingARememberedSlotEachFindTheirOwnRow) {
  ionode::od::IoNodeValues values{};
  const ObjectDictionary od(ionode::od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  ASSERT_GT(2 * od.row_count(), 256);  // more keys than the host's 256 slots
  for (int round = 0; round < 3; ++round) {
    for (uint16_t row = 0; row < od.row_count(); ++row) {
      const OdEntry e = od.entry(row);
      EXPECT_EQ(od.find(e.index, e.sub), row);
      EXPECT_EQ(od.find(e.index, 0xFF), kNoRow) << std::hex << e.index;  // no OD here has sub FFh
    }
  }
  EXPECT_EQ(od.find(0x0000, 0), kNoRow);  // key 0 + 1: not an empty slot's
}

// The table keeps where a value is, never the value: a value changed by
// write(), set() or a raw ram() write reads as changed at once, and so does
// a node-id-relative constant after the node id changes (decoded, not kept).
TEST(OdDirect, AWriteIsReadAtOnceThroughTheTable) {
  ionode::od::IoNodeValues values{};
  ObjectDictionary od(ionode::od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  const uint16_t heartbeat = od.find(0x1017, 0);  // U16, RAM
  ASSERT_EQ(od.size_of(heartbeat), 2u);
  const uint8_t ms[2] = {0x34, 0x12};
  ASSERT_EQ(od.write(0x1017, 0, ms, 2), kSdoOk);
  EXPECT_EQ(od.get(heartbeat), 0x1234u);
  od.set(heartbeat, 0xBEEF);
  EXPECT_EQ(od.get(heartbeat), 0xBEEFu);
  od.ram(heartbeat)[1] = 0x01;
  EXPECT_EQ(od.get(heartbeat), 0x01EFu);
  uint8_t bytes[4] = {};
  EXPECT_EQ(od.copy_out(heartbeat, bytes, sizeof bytes), 2u);
  EXPECT_EQ(bytes[0], 0xEF);
  EXPECT_EQ(bytes[1], 0x01);

  // set() changes only the row's own bytes, and says (and counts) a change
  // only when one was made.
  const uint8_t* value = od.ram_untracked(heartbeat);
  ASSERT_LE(value + 4, reinterpret_cast<const uint8_t*>(&values) + sizeof values);
  const uint8_t beyond[2] = {value[2], value[3]};  // the bytes of whatever follows 1017h
  const uint16_t revision = od.revision();
  // Bits above the row's 16 that differ from the bytes beyond it.
  const uint32_t high = static_cast<uint32_t>(static_cast<uint8_t>(~beyond[0]) | (~beyond[1] & 0xFF) << 8)
                        << 16;
  EXPECT_FALSE(od.set(heartbeat, high | 0x01EF));  // the same 16 bits
  EXPECT_EQ(od.revision(), revision);
  EXPECT_TRUE(od.set(heartbeat, high | 0x01EE));
  EXPECT_NE(od.revision(), revision);
  EXPECT_EQ(od.get(heartbeat), 0x01EEu);
  EXPECT_EQ(value[2], beyond[0]);
  EXPECT_EQ(value[3], beyond[1]);

  const uint16_t sdo_rx = od.find(0x1200, 1);  // CONST, 600h + node id
  ASSERT_EQ(od.attr(sdo_rx) & (kAttrRam | kAttrNodeId), kAttrNodeId);
  od.set_node_id(5);
  EXPECT_EQ(od.get(sdo_rx), 0x605u);
  od.set_node_id(9);
  EXPECT_EQ(od.get(sdo_rx), 0x609u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
