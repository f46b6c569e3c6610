// The master's process image (canopen/master/process_image.h): real nodes'
// TPDOs decoded into the mirror with the mapping read from the node (its
// default one, and odd-length ones with dummies set up by the CiA 301 SDO
// procedure), seed 004's PDO frames, short frames, and RPDOs encoded from
// the mirror that a real node applies (on request, on SYNC, on change).
#include <gtest/gtest.h>

#include "canopen/frame_out.h"
#include "canopen/master/nmt_master.h"
#include "canopen/master/process_image.h"
#include "canopen/master/sync_producer.h"
#include "test_master_bus.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Strings = std::vector<std::string>;

/// A master with a process image and one real I/O node (id 3) on the bus.
class MasterImage : public ::testing::Test {
 protected:
  void SetUp() override {
    bus.master_rx = [this](const CanFrame& f, uint32_t t) { image.on_frame(f, t); };
    bus.master_process = [this](uint32_t t) {
      uint8_t counter = 0;
      if (sync.process(t, bus.master_sink(), &counter)) image.on_sync(bus.master_sink());
      image.process(t, bus.master_sink());
    };
  }
  /// An expedited SDO download to node 3 that must be acknowledged.
  void sdo_write(uint16_t index, uint8_t sub, uint32_t value, uint8_t len) {
    uint8_t req[8] = {static_cast<uint8_t>(0x23 | ((4 - len) << 2)), static_cast<uint8_t>(index),
                      static_cast<uint8_t>(index >> 8), sub};
    put_le32(&req[4], value);
    ASSERT_TRUE(send_frame(bus.master_sink(), 0x603, 8, req));
    bus.deliver();
    ASSERT_EQ(bus.trace.back().second.substr(0, 9), "<583> 60 ")
        << std::hex << index << "/" << int(sub) << ": " << bus.trace.back().second;
  }
  /// Remaps node 3's PDO (comm `comm`, mapping `map`) by the CiA 301 procedure.
  void remap(uint16_t comm, uint16_t map, uint32_t cob_id, const std::vector<uint32_t>& entries) {
    sdo_write(comm, 1, cob_id | 0x80000000u, 4);
    sdo_write(map, 0, 0, 1);
    for (size_t k = 0; k < entries.size(); ++k) sdo_write(map, static_cast<uint8_t>(k + 1), entries[k], 4);
    sdo_write(map, 0, static_cast<uint32_t>(entries.size()), 1);
    sdo_write(comm, 1, cob_id, 4);
  }
  /// The node's mapping record `map` as it holds it now (what a master reads by SDO).
  std::vector<uint32_t> mapping_of(uint16_t map) {
    ObjectDictionary& od = node->io.od();
    std::vector<uint32_t> m;
    const uint32_t count = od.get(od.find(map, 0));
    for (uint8_t s = 1; s <= count; ++s) m.push_back(od.get(od.find(map, s)));
    return m;
  }
  uint32_t value(uint16_t index, uint8_t sub) {
    const ImageEntry* e = image.find(3, index, sub);
    EXPECT_NE(e, nullptr) << std::hex << index << "/" << int(sub);
    return e != nullptr ? e->u32() : 0xDEADBEEFu;
  }

  MasterBus bus;
  ProcessImage<8, 16> image;
  SyncProducer sync;
  MasterBus::Station* node = &bus.add_node(3);
};

TEST_F(MasterImage, ARealNodesTpdoWithItsDefaultMappingAsInSeed004) {
  const std::vector<uint32_t> map = mapping_of(0x1A00);
  ASSERT_EQ(map, std::vector<uint32_t>({0x60000108u, 0x60000208u}));
  ASSERT_TRUE(image.configure_tpdo(3, 0, 0x183, map.data(), static_cast<uint8_t>(map.size())));
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  EXPECT_EQ(value(0x6000, 1), 0u);
  node->io.set_input(0, 0x02);
  node->io.set_input(1, 0x81);
  bus.run(1000);
  EXPECT_EQ(bus.take(), Strings({"<703> 00", "<000> 01 03", "<183> 00 00", "<183> 02 81"}));
  EXPECT_EQ(value(0x6000, 1), 0x02u);
  EXPECT_EQ(value(0x6000, 2), 0x81u);
  const ImageEntry* e = image.find(3, 0x6000, 2);
  EXPECT_EQ(e->updates, 2u);
  uint32_t at = 0;
  ASSERT_TRUE(bus.last_time_of("<183> 02 81", &at));
  EXPECT_EQ(e->updated_us, at);
  EXPECT_EQ(image.find(3, 0x6000, 3), nullptr);
  EXPECT_EQ(image.find(4, 0x6000, 1), nullptr);
}

TEST_F(MasterImage, OddLengthsAndDummyEntriesAreDecodedBitExactly) {
  // Inputs 1 as 4 bits, a dummy UNSIGNED8, inputs 2 as 7 bits: 19 bits in 3 bytes.
  remap(0x1800, 0x1A00, 0x183, {0x60000104u, 0x00050008u, 0x60000207u});
  const std::vector<uint32_t> map = mapping_of(0x1A00);
  ASSERT_EQ(map.size(), 3u);
  ASSERT_TRUE(image.configure_tpdo(3, 0, 0x183, map.data(), 3));
  EXPECT_EQ(image.pdo(3, 0, false)->bytes, 3u);
  EXPECT_EQ(image.find(3, 0x0005, 0), nullptr) << "dummies are not mirrored";
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  const uint8_t samples[][2] = {{0xA5, 0xBC}, {0x0F, 0x7F}, {0xF0, 0x80}, {0x5A, 0x01}};
  for (const auto& in : samples) {
    node->io.set_input(0, in[0]);
    node->io.set_input(1, in[1]);
    bus.run(1000);
    EXPECT_EQ(value(0x6000, 1), in[0] & 0x0Fu) << bus.trace.back().second;
    EXPECT_EQ(value(0x6000, 2), in[1] & 0x7Fu) << bus.trace.back().second;
  }
  // The last frame, by hand: 5 at bits 0-3, dummy 4-11, 01 at bits 12-18.
  EXPECT_EQ(bus.trace.back().second, "<183> 0A 10 00");
}

TEST_F(MasterImage, SignedValuesAreSignExtendedFromTheirMappedLength) {
  const uint32_t map[] = {0x20000108u, 0x20000204u, 0x20000304u};
  ASSERT_TRUE(image.configure_tpdo(9, 0, 0x189, map, 3));
  bus.inject(F(0x189, {0xFE, 0x7F}));
  const ImageEntry* a = image.find(9, 0x2000, 1);
  const ImageEntry* b = image.find(9, 0x2000, 2);
  const ImageEntry* c = image.find(9, 0x2000, 3);
  EXPECT_EQ(a->s32(), -2);
  EXPECT_EQ(a->u32(), 0xFEu);
  EXPECT_EQ(b->s32(), -1);  // bits 8-11: 1111b
  EXPECT_EQ(b->u32(), 0xFu);
  EXPECT_EQ(c->s32(), 7);  // bits 12-15: 0111b
}

TEST_F(MasterImage, AFrameShorterThanTheMappingIsIgnoredAndCounted) {
  const uint32_t map[] = {0x60000108u, 0x60000208u};
  ASSERT_TRUE(image.configure_tpdo(3, 0, 0x183, map, 2));
  bus.inject(F(0x183, {0x02, 0x81}));  // seed 004
  bus.inject(F(0x183, {0x33}));
  EXPECT_EQ(value(0x6000, 1), 0x02u);
  EXPECT_EQ(value(0x6000, 2), 0x81u);
  EXPECT_EQ(image.find(3, 0x6000, 1)->updates, 1u);
  EXPECT_EQ(image.pdo_length_errors(), 1u);
  EXPECT_EQ(image.pdo(3, 0, false)->length_errors, 1u);
  // A longer frame is used for its mapped part.
  bus.inject(F(0x183, {0x04, 0x05, 0x06}));
  EXPECT_EQ(value(0x6000, 1), 0x04u);
  EXPECT_EQ(value(0x6000, 2), 0x05u);
  EXPECT_EQ(image.pdo_length_errors(), 1u);
  // RTR and other ids are not TPDOs of the image.
  EXPECT_FALSE(image.on_frame(Rtr(0x183, 2), 0));
  EXPECT_FALSE(image.on_frame(F(0x283, {1, 2}), 0));
}

TEST_F(MasterImage, RpdoOnRequestSetsARealNodesOutputsAsInSeed004) {
  const std::vector<uint32_t> map = mapping_of(0x1600);
  ASSERT_TRUE(
      image.configure_rpdo(3, 0, 0x203, map.data(), static_cast<uint8_t>(map.size()), kRpdoOnRequest));
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  bus.take();
  EXPECT_TRUE(image.set(3, 0x6200, 2, 0x01));
  EXPECT_FALSE(image.set(3, 0x6200, 3, 0x01)) << "not mapped: not in the image";
  bus.run(1000);
  EXPECT_TRUE(bus.take().empty()) << "on request only";
  EXPECT_TRUE(image.send_rpdo(3, 0, bus.master_sink()));
  bus.deliver();
  EXPECT_EQ(bus.take(), Strings({"<203> 00 01"}));
  bus.run(100);
  EXPECT_EQ(node->io.output(0), 0x00u);
  EXPECT_EQ(node->io.output(1), 0x01u);
  EXPECT_FALSE(image.send_rpdo(3, 1, bus.master_sink())) << "RPDO2 not configured";
  EXPECT_FALSE(image.send_rpdo(4, 0, bus.master_sink()));
}

TEST_F(MasterImage, RpdoWithOddLengthsAndADummyIsAppliedBitExactlyByARealNode) {
  remap(0x1400, 0x1600, 0x203, {0x62000104u, 0x00050008u, 0x62000206u});
  const std::vector<uint32_t> map = mapping_of(0x1600);
  ASSERT_TRUE(image.configure_rpdo(3, 0, 0x203, map.data(), 3, kRpdoOnRequest));
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  bus.take();
  image.set(3, 0x6200, 1, 0xFA);  // 4 bits of it: A
  image.set(3, 0x6200, 2, 0x2B);  // 6 bits
  EXPECT_EQ(image.find(3, 0x6200, 1)->u32(), 0x0Au) << "the mirror holds what the PDO can carry";
  ASSERT_TRUE(image.send_rpdo(3, 0, bus.master_sink()));
  bus.run(200);
  EXPECT_EQ(bus.take(), Strings({"<203> 0A B0 02"}));
  EXPECT_EQ(node->io.output(0), 0x0Au);
  EXPECT_EQ(node->io.output(1), 0x2Bu);
}

TEST_F(MasterImage, RpdoOnChangeLeavesOnceAfterAChangeAndIsRetriedWhenRefused) {
  const std::vector<uint32_t> map = mapping_of(0x1600);
  ASSERT_TRUE(image.configure_rpdo(3, 0, 0x203, map.data(), 2, kRpdoOnChange));
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  bus.take();
  image.set(3, 0x6200, 1, 0x00);  // no change
  NextDeadline idle(bus.now);
  image.next_deadline(idle);
  uint32_t at = 0;
  EXPECT_FALSE(idle.result(&at));
  image.set(3, 0x6200, 1, 0x11);
  image.set(3, 0x6200, 2, 0x22);
  NextDeadline due(bus.now);
  image.next_deadline(due);
  ASSERT_TRUE(due.result(&at));
  EXPECT_EQ(at, bus.now);
  bus.run(1000);
  EXPECT_EQ(bus.take(), Strings({"<203> 11 22"}));
  EXPECT_EQ(node->io.output(0), 0x11u);

  // The port refuses: still pending, sent once it accepts.
  FrameLog full;
  full.refuse = true;
  image.set(3, 0x6200, 2, 0x23);
  image.process(bus.now, full.sink());
  EXPECT_EQ(image.send_failures(), 1u);
  bus.run(100);
  EXPECT_EQ(bus.take(), Strings({"<203> 11 23"}));
}

TEST_F(MasterImage, RpdoOnSyncLeavesRightAfterEachSync) {
  const std::vector<uint32_t> map = mapping_of(0x1600);
  ASSERT_TRUE(image.configure_rpdo(3, 0, 0x203, map.data(), 2, kRpdoOnSync));
  ASSERT_TRUE(image.set(3, 0x6200, 1, 0x42));
  NmtMaster(bus.master_sink()).start(3);
  bus.run(1000);
  bus.take();
  ASSERT_TRUE(sync.configure(0x80, 10000, 0));
  bus.run(20100);
  EXPECT_EQ(bus.take(), Strings({"<080>", "<203> 42 00", "<080>", "<203> 42 00"}));
  EXPECT_EQ(node->io.output(0), 0x42u);
}

TEST(MasterImageConfig, RefusesBadMappingsAndFullTablesWithoutChangingAnything) {
  ProcessImage<2, 3> image;
  const uint32_t ok[] = {0x60000108u, 0x60000208u};
  EXPECT_FALSE(image.configure_tpdo(0, 0, 0x183, ok, 2));
  EXPECT_FALSE(image.configure_tpdo(128, 0, 0x183, ok, 2));
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x800, ok, 2));
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x183, ok, 0));
  const uint32_t zero_bits[] = {0x60000100u};
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x183, zero_bits, 1));
  const uint32_t too_long[] = {0x20000140u, 0x20000208u};
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x183, too_long, 2)) << "72 bits";
  const uint32_t bad_dummy[] = {0x00050010u};
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x183, bad_dummy, 1)) << "UNSIGNED8 dummy of 16 bits";
  const uint32_t nine[9] = {0x20000101u, 0x20000201u, 0x20000301u, 0x20000401u, 0x20000501u,
                            0x20000601u, 0x20000701u, 0x20000801u, 0x20000901u};
  EXPECT_FALSE(image.configure_tpdo(3, 0, 0x183, nine, 9));
  EXPECT_FALSE(image.configure_rpdo(3, 0, 0x203, ok, 2, static_cast<RpdoTrigger>(7)));
  EXPECT_EQ(image.pdo(3, 0, false), nullptr);

  ASSERT_TRUE(image.configure_tpdo(3, 0, 0x183, ok, 2));
  const uint32_t two_more[] = {0x62000108u, 0x62000208u};
  EXPECT_FALSE(image.configure_rpdo(3, 0, 0x203, two_more, 2, kRpdoOnRequest)) << "3 entry slots";
  EXPECT_EQ(image.pdo(3, 0, true), nullptr);
  EXPECT_EQ(image.find(3, 0x6200, 1), nullptr) << "a refused configuration adds nothing";
  // The same object twice in one mapping needs one slot.
  const uint32_t twice[] = {0x62000108u, 0x62000108u};
  ASSERT_TRUE(image.configure_rpdo(3, 0, 0x203, twice, 2, kRpdoOnRequest));
  const uint32_t other[] = {0x60000108u};
  EXPECT_FALSE(image.configure_tpdo(5, 0, 0x185, other, 1)) << "2 PDO slots";
  // Reconfiguring a PDO reuses its slot.
  const uint32_t one[] = {0x60000108u};
  EXPECT_TRUE(image.configure_tpdo(3, 0, 0x183, one, 1));
  EXPECT_EQ(image.pdo(3, 0, false)->count, 1u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
