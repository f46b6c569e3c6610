// Several RPDOs may subscribe to one producer's COB-ID and map its data
// differently: each of them gets the frame.
#include <gtest/gtest.h>

#include "canopen/od_comm.h"
#include "frame_log.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using namespace canopen;

void write32(ObjectDictionary& od, uint16_t index, uint8_t sub, uint32_t v) {
  uint8_t b[4];
  put_le32(b, v);
  ASSERT_EQ(od.write(index, sub, b, 4), kSdoOk) << std::hex << index << "/" << unsigned(sub);
}

void write8(ObjectDictionary& od, uint16_t index, uint8_t sub, uint8_t v) {
  ASSERT_EQ(od.write(index, sub, &v, 1), kSdoOk) << std::hex << index << "/" << unsigned(sub);
}

TEST(RpdoSharedCobId, EveryRpdoOnTheCobIdAppliesItsOwnMapping) {
  test::FrameLog bus;
  ionode::IoNode node(bus.sink());
  node.start(3, 0);
  ObjectDictionary& od = node.od();
  // RPDO1 (203h): first byte -> 6200h/1, second byte skipped by a dummy.
  write32(od, 0x1400, 1, 0x80000203u);
  write8(od, 0x1600, 0, 0);
  write32(od, 0x1600, 1, MB2CO_PDO_MAP_ENTRY(0x6200, 1, 8));
  write32(od, 0x1600, 2, MB2CO_PDO_MAP_ENTRY(0x0005, 0, 8));
  write8(od, 0x1600, 0, 2);
  write32(od, 0x1400, 1, 0x203u);
  // RPDO2 on the same COB-ID: first byte skipped, second byte -> 6200h/2.
  write8(od, 0x1601, 0, 0);
  write32(od, 0x1601, 1, MB2CO_PDO_MAP_ENTRY(0x0005, 0, 8));
  write32(od, 0x1601, 2, MB2CO_PDO_MAP_ENTRY(0x6200, 2, 8));
  write8(od, 0x1601, 0, 2);
  write32(od, 0x1401, 1, 0x203u);
  node.receive(test::F(0x000, {0x01, 0x03}), 1000);
  node.receive(test::F(0x203, {0x11, 0x22}), 2000);
  EXPECT_EQ(node.output(0), 0x11);
  EXPECT_EQ(node.output(1), 0x22);
}

}  // namespace
}  // namespace mb2co
