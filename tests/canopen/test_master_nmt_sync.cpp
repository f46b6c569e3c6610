// The master's NMT commands (canopen/master/nmt_master.h) and SYNC producer
// (canopen/master/sync_producer.h): their frames byte for byte, and their
// effect on real nodes of the node core on a virtual bus (states changed,
// boot-ups after resets, synchronous TPDOs on every SYNC, the 1019h counter).
#include <gtest/gtest.h>

#include "canopen/frame_out.h"
#include "canopen/master/nmt_master.h"
#include "canopen/master/sync_producer.h"
#include "test_master_bus.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Strings = std::vector<std::string>;

TEST(MasterNmt, TheFiveCommandsToOneNodeOrAll) {
  FrameLog log;
  NmtMaster nmt(log.sink());
  EXPECT_TRUE(nmt.start(3));
  EXPECT_TRUE(nmt.stop(3));
  EXPECT_TRUE(nmt.enter_pre_operational(127));
  EXPECT_TRUE(nmt.reset_node(NmtMaster::kAllNodes));
  EXPECT_TRUE(nmt.reset_communication(5));
  EXPECT_EQ(log.take(), Strings({"<000> 01 03", "<000> 02 03", "<000> 80 7F", "<000> 81 00", "<000> 82 05"}));
}

TEST(MasterNmt, RefusesUnknownCommandsAndNodeIdsAndCountsRefusedFrames) {
  FrameLog log;
  NmtMaster nmt(log.sink());
  EXPECT_FALSE(nmt.command(static_cast<NmtCommand>(0x03), 3));
  EXPECT_FALSE(nmt.start(128));
  EXPECT_TRUE(log.take().empty());
  log.refuse = true;
  EXPECT_FALSE(nmt.stop(3));
  EXPECT_EQ(nmt.send_failures(), 1u);
}

TEST(MasterNmt, CommandsChangeTheStateOfRealNodes) {
  MasterBus bus;
  NmtMaster nmt(bus.master_sink());
  MasterBus::Station& n3 = bus.add_node(3);
  MasterBus::Station& n5 = bus.add_node(5);
  EXPECT_EQ(bus.take(), Strings({"<703> 00", "<705> 00"}));
  EXPECT_EQ(n3.io.node().nmt_state(), kNmtPreOperational);

  nmt.start(3);
  bus.step(100);
  EXPECT_EQ(n3.io.node().nmt_state(), kNmtOperational);
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtPreOperational) << "addressed to node 3 only";
  nmt.start(NmtMaster::kAllNodes);
  bus.step(100);
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtOperational);
  nmt.stop(5);
  bus.step(100);
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtStopped);
  EXPECT_EQ(n3.io.node().nmt_state(), kNmtOperational);
  nmt.enter_pre_operational(NmtMaster::kAllNodes);
  bus.step(100);
  EXPECT_EQ(n3.io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtPreOperational);
  bus.take();

  // Resets: the node answers with its boot-up and is pre-operational again.
  nmt.start(NmtMaster::kAllNodes);
  bus.run(1000);  // entering operational, both send their TPDO1
  EXPECT_EQ(bus.take(), Strings({"<000> 01 00", "<183> 00 00", "<185> 00 00"}));
  nmt.reset_communication(3);
  bus.step(100);
  EXPECT_EQ(bus.take(), Strings({"<000> 82 03", "<703> 00"}));
  EXPECT_EQ(n3.io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtOperational);
  nmt.reset_node(NmtMaster::kAllNodes);
  bus.step(100);
  EXPECT_EQ(bus.take(), Strings({"<000> 81 00", "<703> 00", "<705> 00"}));
  EXPECT_EQ(n5.io.node().nmt_state(), kNmtPreOperational);
}

TEST(MasterSync, NoCounterFrameEveryPeriodExactly) {
  FrameLog log;
  SyncProducer sync;
  ASSERT_TRUE(sync.configure(0x40000080u, 10000, 0));
  uint32_t now = 0xFFFFF000u;  // across the clock's wrap
  NextDeadline d0(now);
  sync.next_deadline(d0);
  uint32_t at = 0;
  ASSERT_TRUE(d0.result(&at));
  EXPECT_EQ(at, now) << "the period starts at the next process()";
  EXPECT_FALSE(sync.process(now, log.sink()));
  const uint32_t start = now;
  for (int k = 1; k <= 3; ++k) {
    NextDeadline d(now);
    sync.next_deadline(d);
    ASSERT_TRUE(d.result(&at));
    EXPECT_EQ(at, start + 10000u * static_cast<uint32_t>(k));
    uint8_t counter = 0xAA;
    EXPECT_FALSE(sync.process(at - 1, log.sink(), &counter));
    EXPECT_TRUE(sync.process(at, log.sink(), &counter));
    EXPECT_EQ(counter, 0u);
    now = at;
  }
  EXPECT_EQ(log.take(), Strings({"<080>", "<080>", "<080>"}));
  ASSERT_EQ(log.frames.size(), 0u);
}

TEST(MasterSync, CounterRunsOneToOverflowInTheFramesOneByte) {
  FrameLog log;
  SyncProducer sync;
  ASSERT_TRUE(sync.configure(0x80, 1000, 3));
  sync.process(0, log.sink());
  for (uint32_t t = 1000; t <= 5000; t += 1000) sync.process(t, log.sink());
  EXPECT_EQ(log.take(), Strings({"<080> 01", "<080> 02", "<080> 03", "<080> 01", "<080> 02"}));
}

TEST(MasterSync, RefusesWhatCiA301DoesNotAllowAndStopsAtPeriodZero) {
  SyncProducer sync;
  EXPECT_FALSE(sync.configure(0x80, 1000, 1)) << "1019h = 1 is reserved";
  EXPECT_FALSE(sync.configure(0x80, 1000, 241));
  EXPECT_FALSE(sync.configure(0x20000080u, 1000, 0)) << "29-bit ids";
  EXPECT_EQ(sync.period_us(), 0u);
  FrameLog log;
  for (uint32_t t = 0; t < 100000; t += 1000) EXPECT_FALSE(sync.process(t, log.sink()));
  NextDeadline d(0);
  sync.next_deadline(d);
  uint32_t at = 0;
  EXPECT_FALSE(d.result(&at));
  EXPECT_TRUE(log.take().empty());
}

TEST(MasterSync, ARefusedSyncIsCountedAndTheNextKeepsThePhase) {
  FrameLog log;
  SyncProducer sync;
  ASSERT_TRUE(sync.configure(0x80, 1000, 2));
  sync.process(0, log.sink());
  log.refuse = true;
  EXPECT_FALSE(sync.process(1000, log.sink()));
  EXPECT_EQ(sync.send_failures(), 1u);
  log.refuse = false;
  EXPECT_FALSE(sync.process(1500, log.sink())) << "not repeated late";
  EXPECT_TRUE(sync.process(2000, log.sink()));
  EXPECT_EQ(log.take(), Strings({"<080> 02"})) << "the lost SYNC's counter is skipped";
  // A pause of several periods gives one SYNC, not a burst.
  EXPECT_TRUE(sync.process(9500, log.sink()));
  EXPECT_FALSE(sync.process(9600, log.sink()));
  EXPECT_EQ(log.take().size(), 1u);
}

/// A real node with TPDO1 synchronous (type 1): it answers every SYNC.
TEST(MasterSync, ARealNodesSynchronousTpdoFollowsEverySyncWithTheCounter) {
  MasterBus bus;
  SyncProducer sync;
  bus.master_process = [&](uint32_t t) { sync.process(t, bus.master_sink()); };
  MasterBus::Station& node = bus.add_node(3);
  const CanSink sink = bus.master_sink();
  const uint8_t type1[8] = {0x2F, 0x00, 0x18, 0x02, 0x01, 0x00, 0x00, 0x00};      // 1800h/2 = 1
  const uint8_t overflow4[8] = {0x2F, 0x19, 0x10, 0x00, 0x04, 0x00, 0x00, 0x00};  // 1019h = 4
  ASSERT_TRUE(send_frame(sink, 0x603, 8, type1));
  ASSERT_TRUE(send_frame(sink, 0x603, 8, overflow4));
  NmtMaster(sink).start(3);
  bus.deliver();
  node.io.set_input(0, 0x5A);
  bus.take();
  ASSERT_TRUE(sync.configure(0x80, 10000, 4));
  bus.run(50100);  // the period starts at the first process(), 100 µs on
  EXPECT_EQ(bus.take(), Strings({"<080> 01", "<183> 5A 00", "<080> 02", "<183> 5A 00", "<080> 03",
                                 "<183> 5A 00", "<080> 04", "<183> 5A 00", "<080> 01", "<183> 5A 00"}));
  // A SYNC without the counter the node expects is a SYNC length error (EMCY 8240h).
  ASSERT_TRUE(sync.configure(0x80, 10000, 0));
  bus.run(10200);  // the node sends its EMCY at its next process()
  EXPECT_EQ(bus.take(), Strings({"<080>", "<083> 40 82 11 00 00 00 00 00"}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
