// NMT slave (CiA 301 §7.3.2): boot-up, the five commands, addressing, and
// what each state lets through; resets and what they restore.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Nmt = IoNodeTest;

TEST(NmtBoot, BootUpMessageThenPreOperational) {
  FrameLog bus;
  ionode::IoNode io(bus.sink());
  EXPECT_EQ(io.node().nmt_state(), kNmtInitialising);
  // Before start() the node says nothing and takes nothing.
  io.receive(F(0x000, {0x01, 0x00}), 0);
  io.receive(F(0x603, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}), 0);
  io.process(0);
  EXPECT_EQ(bus.take(), Frames({}));
  io.start(0x7F, 10);
  EXPECT_EQ(bus.take(), Frames({"<77F> 00"}));
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(io.node().node_id(), 0x7F);
}

TEST_F(Nmt, EveryCommandChangesTheState) {
  h.nmt(0x01, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtOperational);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"})) << "event TPDO on entering operational";
  h.nmt(0x80, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  h.nmt(0x02, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtStopped);
  h.nmt(0x80, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  h.nmt(0x02, kId);
  h.nmt(0x01, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtOperational);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  h.nmt(0x81, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  h.nmt(0x02, kId);
  h.nmt(0x82, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Nmt, NodeIdZeroAddressesAllNodes) {
  h.nmt(0x01, 0);
  EXPECT_EQ(io.node().nmt_state(), kNmtOperational);
  h.nmt(0x02, 0);
  EXPECT_EQ(io.node().nmt_state(), kNmtStopped);
  h.nmt(0x80, 0);
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  h.take();
  h.nmt(0x82, 0);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  h.nmt(0x81, 0);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
}

TEST_F(Nmt, CommandsForOtherNodesAreIgnored) {
  for (unsigned other = 1; other < 256; ++other) {
    if (other == kId) continue;
    for (int cmd : {0x01, 0x02, 0x80, 0x81, 0x82})
      h.nmt(static_cast<uint8_t>(cmd), static_cast<uint8_t>(other));
  }
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Nmt, WrongLengthRtrUnknownCommandsAndExtendedFramesAreIgnored) {
  ASSERT_EQ(h.write_u16(0x2101, 0, 77), 0u);
  for (uint8_t dlc = 0; dlc <= 8; ++dlc) {
    if (dlc == 2) continue;
    for (int cmd : {0x01, 0x02, 0x81, 0x82}) {
      CanFrame f = F(0x000, {static_cast<uint8_t>(cmd), 0, 0, 0, 0, 0, 0, 0});
      f.dlc = dlc;
      h.rx(f);
    }
  }
  h.rx(Rtr(0x000, 2));
  CanFrame ext = F(0x000, {0x82, 0x00});
  ext.flags = CanFrame::kExtended;
  h.rx(ext);
  for (unsigned cmd = 0; cmd < 256; ++cmd) {
    if (cmd == 0x01 || cmd == 0x02 || cmd == 0x80 || cmd == 0x81 || cmd == 0x82) continue;
    h.nmt(static_cast<uint8_t>(cmd), kId);
    h.nmt(static_cast<uint8_t>(cmd), 0);
  }
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_EQ(value(0x2101, 0), 77u) << "no reset happened";
}

TEST_F(Nmt, StoppedAnswersNoSdoSendsNoPdoNoEmcyButKeepsTheHeartbeat) {
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);
  h.nmt(0x01, kId);
  h.take();
  h.nmt(0x02, kId);
  EXPECT_TRUE(h.sdo_exchange({0x40, 0x00, 0x10, 0x00}).empty());
  EXPECT_TRUE(h.sdo_exchange({0x2B, 0x01, 0x21, 0x00, 0x05, 0x00, 0, 0}).empty());
  EXPECT_EQ(value(0x2101, 0), 10u) << "a write in stopped is not carried out";
  io.set_input(0, 0x11);         // would trigger TPDO1
  h.rx(F(0x203, {0x01, 0x02}));  // RPDO1: not applied
  h.rx(Rtr(0x183));              // TPDO1 request: not answered
  h.rx(F(0x080, {}));            // SYNC: nothing
  h.rx(F(0x080, {0x01, 0x02}));  // a wrong SYNC: no EMCY in stopped
  io.node().emcy().raise(0x5000, kErrDeviceProfile);
  h.run_us(250000, 1000);
  EXPECT_EQ(h.take(), Frames({"<703> 04", "<703> 04"}));
  EXPECT_EQ(io.output(0), 0);
  // The EMCY is held back, not lost: it leaves once the node may send it.
  // (The wrong SYNC was not even looked at: SYNC is not consumed in stopped.)
  h.nmt(0x80, kId);
  EXPECT_EQ(h.take(), Frames({"<083> 00 50 21 00 00 00 00 00"}));
}

TEST_F(Nmt, PreOperationalAnswersSdoButNoPdo) {
  io.set_input(0, 0x11);
  h.rx(F(0x203, {0x01, 0x02}));
  h.rx(Rtr(0x183));
  h.rx(F(0x080, {}));
  h.run_us(100000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_EQ(h.read(0x6000, 1), 0x11u);
  // Entering operational publishes the current inputs.
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> 11 00"}));
}

TEST_F(Nmt, LeavingOperationalStopsPdosAtOnce) {
  operational();
  io.set_input(1, 0x22);
  h.nmt(0x80, kId);  // before process() could send the change
  EXPECT_EQ(h.take(), Frames({}));
  h.run_us(10000);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Nmt, StopCancelsASegmentedTransfer) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  h.nmt(0x02, kId);
  h.run_us(2000000, 10000);  // no timeout abort from a stopped node
  EXPECT_EQ(h.take(), Frames({}));
  h.nmt(0x80, kId);
  h.expect_abort({0x60}, 0x1008, 0, kAbortCommand);
}

TEST_F(Nmt, ResetCommunicationRestoresOnlyTheCommunicationArea) {
  operational();
  ASSERT_EQ(h.write_u16(0x1017, 0, 1000), 0u);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 1), 0u);
  ASSERT_EQ(h.write_u32(0x1016, 1, 0x00050064u), 0u);
  ASSERT_EQ(h.write_u16(0x1015, 0, 10), 0u);
  ASSERT_EQ(h.write_u16(0x2101, 0, 99), 0u);
  ASSERT_EQ(h.download(0x2000, 0, bytes_of("kept over reset comm")), 0u);
  ASSERT_EQ(h.write_u8(0x6200, 1, 0x5A), 0u);
  h.nmt(0x82, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  EXPECT_EQ(h.read(0x1017, 0), 0u);
  EXPECT_EQ(h.read(0x1800, 1), 0x183u);
  EXPECT_EQ(h.read(0x1A00, 0), 2u);
  EXPECT_EQ(h.read(0x1016, 1), 0u);
  EXPECT_EQ(h.read(0x1015, 0), 0u);
  EXPECT_EQ(h.read(0x1000, 0), 0x00030191u);
  EXPECT_EQ(h.read(0x2101, 0), 99u);
  EXPECT_EQ(h.read_string(0x2000, 0), "kept over reset comm");
  EXPECT_EQ(h.read(0x6200, 1), 0x5Au);
  // The restored heartbeat time means: no heartbeat.
  h.run_us(2000000, 10000);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Nmt, ResetNodeRestoresEverything) {
  operational();
  ASSERT_EQ(h.write_u16(0x1017, 0, 1000), 0u);
  ASSERT_EQ(h.write_u16(0x2101, 0, 99), 0u);
  ASSERT_EQ(h.write_u8(0x2100, 0, 1), 0u);
  ASSERT_EQ(h.download(0x2000, 0, bytes_of("gone after reset node")), 0u);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_EQ(h.read(0x1017, 0), 0u);
  EXPECT_EQ(h.read(0x2101, 0), 10u);
  EXPECT_EQ(h.read(0x2100, 0), 0u);
  EXPECT_EQ(h.read_string(0x2000, 0), "");
  EXPECT_EQ(h.read(0x1000, 0), 0x00030191u);
}

TEST_F(Nmt, ResetClearsErrorsAndTheHistory) {
  io.node().emcy().raise(0x5000, kErrDeviceProfile);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<083> 00 50 21 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1001, 0), 0x21u);
  EXPECT_EQ(h.read(0x1003, 0), 1u);
  h.nmt(0x82, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  EXPECT_EQ(h.read(0x1001, 0), 0u);
  EXPECT_EQ(h.read(0x1003, 0), 0u);
  EXPECT_FALSE(io.node().emcy().active(0x5000));
}

TEST_F(Nmt, NodeIdChangesAtResetCommunication) {
  io.node().set_node_id_for_next_reset(0x10);
  EXPECT_EQ(h.read(0x1014, 0), 0x83u);  // still 3 until the reset
  h.nmt(0x82, kId);
  EXPECT_EQ(h.take(), Frames({"<710> 00"}));
  EXPECT_EQ(io.node().node_id(), 0x10);
  EXPECT_EQ(h.read(0x1014, 0), 0x90u);
  EXPECT_EQ(h.read(0x1800, 1), 0x190u);
  EXPECT_EQ(h.read(0x1400, 1), 0x210u);
  EXPECT_EQ(h.read(0x1200, 1), 0x610u);
  // Commands for the old id are not ours any more.
  h.nmt(0x01, kId);
  EXPECT_EQ(io.node().nmt_state(), kNmtPreOperational);
  h.nmt(0x01, 0x10);
  EXPECT_EQ(io.node().nmt_state(), kNmtOperational);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
