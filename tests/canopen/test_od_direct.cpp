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

// Keys that share a remembered slot (index * 31 + sub, modulo 256: sub 31
// of an index and sub 0 of the next) and absent keys: each asked in turn
// answers its own row, or kNoRow, never the slot's previous key's.
TEST(OdDirect, KeysSharingARememberedSlotEachFindTheirOwnRow) {
  ionode::od::IoNodeValues values{};
  const ObjectDictionary od(ionode::od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values));
  const uint16_t heartbeat = od.find(0x1017, 0);
  const uint16_t emcy = od.find(0x1014, 0);
  ASSERT_NE(heartbeat, kNoRow);
  ASSERT_NE(emcy, kNoRow);
  for (int round = 0; round < 3; ++round) {
    EXPECT_EQ(od.find(0x1016, 31), kNoRow);  // the slot of 1017h/0
    EXPECT_EQ(od.find(0x1017, 0), heartbeat);
    EXPECT_EQ(od.find(0x1013, 31), kNoRow);  // the slot of 1014h/0
    EXPECT_EQ(od.find(0x1014, 0), emcy);
    EXPECT_EQ(od.find(0x1014, 1), kNoRow);
    EXPECT_EQ(od.find(0x0000, 0), kNoRow);  // key 0 + 1: not an empty slot
  }
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
