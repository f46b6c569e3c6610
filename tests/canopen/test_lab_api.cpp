// The lab API of seed 000 §3.3–3.5 on the I/O test node's OD.
#include <gtest/gtest.h>

#include <cstring>

#include "canopen/od_lab_api.h"
#include "frame_log.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using namespace canopen;

class LabApi : public ::testing::Test {
 protected:
  test::FrameLog bus;
  ionode::IoNode node{bus.sink()};
  void SetUp() override {
    node.start(3, 0);
    od_bind(&node.od());
  }
  void TearDown() override { od_bind(nullptr); }
};

TEST_F(LabApi, SizesComeFromTheDataTypeEntries) {
  uint8_t size = 0;
  EXPECT_EQ(od_getsize_subentry(0x1017, 0, &size), 0);
  EXPECT_EQ(size, 2);  // UNSIGNED16: 0006h holds 16 bits
  EXPECT_EQ(od_getsize_subentry(0x1000, 0, &size), 0);
  EXPECT_EQ(size, 4);
  EXPECT_EQ(od_getsize_subentry(0x0003, 0, &size), 0);  // the data-type entry itself
  EXPECT_EQ(size, 4);
  // 1018h: sub 0 (u8) + 4 x u32
  EXPECT_EQ(od_getsize_object(0x1018, &size), 0);
  EXPECT_EQ(size, 17);
  EXPECT_EQ(od_getsize_object(0x2000, &size), 0);  // string: its capacity
  EXPECT_EQ(size, 24);
}

TEST_F(LabApi, ReadsObjectsAndSubentriesLittleEndian) {
  uint8_t data[32] = {};
  uint8_t size = 0;
  ASSERT_EQ(od_read_subentry(0x1000, 0, data, &size), 0);
  EXPECT_EQ(size, 4);
  EXPECT_EQ(le32(data), 0x00030191u);
  ASSERT_EQ(od_read_object(0x6000, data, &size), 0);
  EXPECT_EQ(size, 3);
  EXPECT_EQ(data[0], 2);  // sub 0: two inputs
}

TEST_F(LabApi, ErrorsAreNegative) {
  uint8_t data[8] = {};
  uint8_t size = 0;
  EXPECT_EQ(od_getsize_object(0x5555, &size), kOdLabNoObject);
  EXPECT_EQ(od_getsize_subentry(0x1018, 9, &size), kOdLabNoSubentry);
  EXPECT_EQ(od_read_subentry(0x5555, 0, data, &size), kOdLabNoObject);
  EXPECT_EQ(od_write_subentry(0x1018, 1, data), kOdLabReadOnly);  // const
  od_bind(nullptr);
  EXPECT_EQ(od_getsize_object(0x1000, &size), kOdLabNotBound);
}

TEST_F(LabApi, WritesGoThroughTheOwningServiceLikeAnSdo) {
  // 1017h = 100 ms via the lab API restarts the heartbeat producer.
  uint8_t v[2];
  put_le16(v, 100);
  ASSERT_EQ(od_write_subentry(0x1017, 0, v), 0);
  node.process(0);  // the producer restarts its period here
  bus.take();
  node.process(99000);
  EXPECT_TRUE(bus.take().empty());
  node.process(100000);
  EXPECT_EQ(bus.take(), std::vector<std::string>({"<703> 7F"}));
  // Limits hold: 2101h is 1..250.
  put_le16(v, 251);
  EXPECT_EQ(od_write_subentry(0x2101, 0, v), kOdLabRefused);
}

TEST_F(LabApi, TheDeviceWritesItsOwnReadOnlyInputs) {
  const uint8_t in = 0x5A;
  ASSERT_EQ(od_write_subentry(0x6000, 1, &in), 0);
  EXPECT_EQ(node.od().get(node.od().find(0x6000, 1)), 0x5Au);
}

TEST_F(LabApi, WriteObjectIsAllOrNothing) {
  // 1800h: sub0 (const) | COB-ID u32 | type u8 | inhibit u16 | event u16 | sync start u8.
  uint8_t data[12] = {};
  uint8_t size = 0;
  ASSERT_EQ(od_read_object(0x1800, data, &size), 0);
  ASSERT_EQ(size, 11);
  uint8_t changed[12];
  std::memcpy(changed, data, sizeof changed);
  changed[5] = 245;            // transmission type 245 is reserved: refused
  put_le16(&changed[8], 500);  // event timer would change
  EXPECT_EQ(od_write_object(0x1800, changed), kOdLabRefused);
  uint8_t after[12] = {};
  ASSERT_EQ(od_read_object(0x1800, after, &size), 0);
  EXPECT_EQ(std::memcmp(after, data, 11), 0);
  changed[5] = 254;
  EXPECT_EQ(od_write_object(0x1800, changed), 0);
  EXPECT_EQ(node.od().get(node.od().find(0x1800, 5)), 500u);
}

// A refused object carries nothing out: 1016h with sub 1 watching node 5
// and sub 2 watching node 5 again (refused: one time per node id) does not
// start a consumer for node 5 (before, sub 1's hook had configured it and
// only its value was put back: node 5's heartbeats were then watched).
TEST_F(LabApi, ARefusedObjectWriteStartsNoService) {
  uint8_t data[17] = {};
  uint8_t size = 0;
  ASSERT_EQ(od_read_object(0x1016, data, &size), 0);
  ASSERT_EQ(size, 17);
  put_le32(&data[1], 0x00050064u);  // node 5, 100 ms
  put_le32(&data[5], 0x000500C8u);  // node 5 again, 200 ms: refused
  EXPECT_EQ(od_write_object(0x1016, data), kOdLabRefused);
  EXPECT_EQ(node.od().get(node.od().find(0x1016, 1)), 0u);
  node.receive(test::F(0x705, {0x05}), 1000);  // node 5's heartbeat, then silence
  bus.take();
  for (uint32_t t = 10000; t <= 1000000; t += 10000) node.process(t);
  EXPECT_TRUE(bus.take().empty()) << "a heartbeat consumer runs although its write was refused";
}

}  // namespace
}  // namespace mb2co
