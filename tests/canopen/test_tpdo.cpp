// Transmit PDOs (CiA 301 §7.2.2): default COB-IDs, dynamic mapping by the
// CiA 301 procedure, every transmission type, inhibit time, event timer,
// RTR, disabled PDOs and a refusing transmit queue.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Tpdo = IoNodeTest;

TEST_F(Tpdo, DefaultCobIdsFollowTheNodeId) {
  EXPECT_EQ(h.read(0x1800, 1), 0x183u);
  EXPECT_EQ(h.read(0x1801, 1), 0x80000283u);
  EXPECT_EQ(h.read(0x1802, 1), 0x80000383u);
  EXPECT_EQ(h.read(0x1803, 1), 0x80000483u);
  EXPECT_EQ(h.read(0x1400, 1), 0x203u);
  EXPECT_EQ(h.read(0x1401, 1), 0x80000303u);
  EXPECT_EQ(h.read(0x1402, 1), 0x80000403u);
  EXPECT_EQ(h.read(0x1403, 1), 0x80000503u);
  EXPECT_EQ(h.read(0x1800, 0), 6u);
  EXPECT_EQ(h.read(0x1400, 0), 5u);
  EXPECT_EQ(h.read(0x1A00, 0), 2u);
  EXPECT_EQ(h.read(0x1A00, 1), 0x60000108u);
  EXPECT_EQ(h.read(0x1A00, 2), 0x60000208u);
  EXPECT_EQ(h.read(0x1600, 1), 0x62000108u);
}

TEST(TpdoNodeId, DefaultsForNodeId127) {
  FrameLog bus;
  ionode::IoNode io(bus.sink());
  Harness h(io.node(), bus);
  io.start(127, 0);
  EXPECT_EQ(h.read(0x1800, 1), 0x1FFu);
  EXPECT_EQ(h.read(0x1803, 1), 0x800004FFu);
  EXPECT_EQ(h.read(0x1400, 1), 0x27Fu);
  EXPECT_EQ(h.read(0x1014, 0), 0xFFu);
}

TEST_F(Tpdo, DynamicMappingByTheCiA301Procedure) {
  // 1. Disable the PDO (bit 31), 2. sub 0 := 0, 3. entries, 4. sub 0 := n, 5. enable.
  ASSERT_EQ(h.write_u32(0x1801, 1, 0x80000283u), 0u);
  ASSERT_EQ(h.write_u8(0x1A01, 0, 0), 0u);
  ASSERT_EQ(h.write_u32(0x1A01, 1, 0x60000208u), 0u);
  ASSERT_EQ(h.write_u32(0x1A01, 2, 0x10010008u), 0u);
  ASSERT_EQ(h.write_u32(0x1A01, 3, 0x60000108u), 0u);
  ASSERT_EQ(h.write_u8(0x1A01, 0, 3), 0u);
  ASSERT_EQ(h.write_u32(0x1801, 1, 0x00000283u), 0u);
  io.set_input(0, 0xAA);
  io.set_input(1, 0xBB);
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> AA BB", "<283> BB 00 AA"}));
  io.set_input(1, 0xBC);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> AA BC", "<283> BC 00 AA"}));
  EXPECT_EQ(h.read(0x1A01, 0), 3u);
}

TEST_F(Tpdo, MappingProcedureOutOfOrderIsRefusedStepByStep) {
  operational();
  // Step 3 before step 1.
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x08, 0x00, 0x01, 0x10}, 0x1A00, 1, kAbortUnsupported);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  // Step 3 before step 2.
  h.expect_abort({0x23, 0x00, 0x1A, 0x01, 0x08, 0x00, 0x01, 0x10}, 0x1A00, 1, kAbortUnsupported);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 0), 0u);
  ASSERT_EQ(h.write_u32(0x1A00, 1, 0x10010008u), 0u);
  ASSERT_EQ(h.write_u32(0x1A00, 2, 0u), 0u);  // clearing an entry is always fine
  // Step 4 with an entry that is empty.
  const std::vector<CanFrame> r = h.sdo_exchange({0x2F, 0x00, 0x1A, 0x00, 2, 0, 0, 0});
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].data[0], 0x80);
  const uint32_t code = le32(&r[0].data[4]);
  EXPECT_TRUE(code == kAbortNoObject || code == kAbortNotMappable) << std::hex << code;
  EXPECT_EQ(h.read(0x1A00, 0), 0u);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 1), 0u);
  // While disabled nothing is sent, not even on a change.
  io.set_input(0, 1);
  h.run_us(10000);
  EXPECT_EQ(h.take(), Frames({}));
  // Step 5.
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 00"}));
}

TEST_F(Tpdo, NoMappedObjectsMeansNoPdo) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u8(0x1A00, 0, 0), 0u);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  operational();
  io.set_input(0, 1);
  h.rx(Rtr(0x183));
  h.rx(F(0x080, {}));
  h.run_us(10000);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Tpdo, Type0IsSentAtTheSyncAfterAChange) {
  ASSERT_EQ(h.write_u8(0x1800, 2, 0), 0u);
  operational();
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"})) << "first SYNC: never sent before";
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({})) << "unchanged: nothing";
  io.set_input(0, 5);
  h.run_us(5000);
  EXPECT_EQ(h.take(), Frames({})) << "changed: waits for the SYNC";
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 05 00"}));
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Tpdo, Types1To240AreSentEveryNthSync) {
  for (const uint8_t type : std::vector<uint8_t>{1, 3, 240}) {
    h.nmt(0x80, kId);
    ASSERT_EQ(h.write_u8(0x1800, 2, type), 0u);
    operational();
    std::vector<int> sent_at;
    for (int k = 1; k <= 3 * type; ++k) {
      h.rx(F(0x080, {}));
      if (!h.take().empty()) sent_at.push_back(k);
    }
    ASSERT_EQ(sent_at.size(), 3u) << "type " << int(type);
    EXPECT_EQ(sent_at[1] - sent_at[0], type);
    EXPECT_EQ(sent_at[2] - sent_at[1], type);
    // Changes between SYNCs do not trigger anything.
    io.set_input(0, static_cast<uint8_t>(type));
    h.run_us(5000);
    EXPECT_EQ(h.take(), Frames({}));
  }
}

TEST_F(Tpdo, Type252IsSampledAtSyncAndSentOnRtr) {
  ASSERT_EQ(h.write_u8(0x1800, 2, 252), 0u);
  operational();
  io.set_input(0, 0x11);
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({})) << "sampled, not sent";
  io.set_input(0, 0x22);
  h.run_us(5000);
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({"<183> 11 00"})) << "the value at the SYNC";
  h.rx(F(0x080, {}));
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({"<183> 22 00"}));
}

TEST_F(Tpdo, Type252BeforeTheFirstSyncAnswersWithTheMappedLength) {
  // Nothing sampled yet: the answer still has the mapped length (a 0-byte
  // PDO would be a length error, EMCY 8210h, at every consumer).
  ASSERT_EQ(h.write_u8(0x1800, 2, 252), 0u);
  operational();
  io.set_input(0, 0x44);
  h.rx(Rtr(0x183));
  const std::vector<CanFrame> f = h.take_frames();
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].dlc, 2);
  EXPECT_EQ(to_string(f[0]), "<183> 44 00");
}

TEST_F(Tpdo, Type253IsSentOnRtrOnly) {
  ASSERT_EQ(h.write_u8(0x1800, 2, 253), 0u);
  operational();
  io.set_input(0, 0x33);
  h.rx(F(0x080, {}));
  h.run_us(5000);
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({"<183> 33 00"}));
  io.set_input(0, 0x34);
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({"<183> 34 00"}));
}

TEST_F(Tpdo, EventTypesAreSentOnChange) {
  for (const uint8_t type : std::vector<uint8_t>{254, 255}) {
    h.nmt(0x80, kId);
    ASSERT_EQ(h.write_u8(0x1800, 2, type), 0u);
    h.nmt(0x01, kId);
    EXPECT_EQ(h.take().size(), 1u) << "the current value on entering operational";
    h.run_us(50000);
    EXPECT_EQ(h.take(), Frames({})) << "no change, no event timer: silence";
    io.set_input(1, type);
    h.advance_us(100);
    EXPECT_EQ(h.take().size(), 1u);
    io.set_input(1, type);  // same value: not a change
    h.advance_us(100);
    EXPECT_EQ(h.take(), Frames({}));
  }
}

TEST_F(Tpdo, InhibitTimeIn100MicrosecondUnits) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u16(0x1800, 3, 50), 0u);  // 5 ms
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  const uint32_t t0 = h.now;
  h.advance_us(1000);
  io.set_input(0, 1);
  h.advance_us(1000);
  io.set_input(0, 2);  // the latest value goes out when the inhibit time is over
  while (h.now - t0 < 4999) {
    h.advance_us(1);
    ASSERT_EQ(h.take(), Frames({})) << "at " << (h.now - t0);
  }
  h.advance_us(1);
  EXPECT_EQ(h.take(), Frames({"<183> 02 00"}));
  // The next change after the inhibit time goes at once.
  h.run_us(6000);
  io.set_input(0, 3);
  h.advance_us(1);
  EXPECT_EQ(h.take(), Frames({"<183> 03 00"}));
}

TEST_F(Tpdo, EventTimerResendsWithoutChange) {
  ASSERT_EQ(h.write_u16(0x1800, 5, 100), 0u);  // ms
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  std::vector<uint32_t> at;
  const uint32_t t0 = h.now;
  for (int i = 0; i < 3500; ++i) {
    h.advance_us(100);
    if (!h.take().empty()) at.push_back((h.now - t0) / 1000);
  }
  EXPECT_EQ(at, std::vector<uint32_t>({100, 200, 300}));
  // A change restarts the timer.
  h.run_us(20000);  // 370 ms
  io.set_input(0, 9);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 09 00"}));
  h.run_us(99800);
  EXPECT_EQ(h.take(), Frames({}));
  h.run_us(200);
  EXPECT_EQ(h.take(), Frames({"<183> 09 00"}));
  // 0 switches it off, at once (the write restarts the timer: below).
  ASSERT_EQ(h.write_u16(0x1800, 5, 0), 0u);
  h.run_us(600000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
}

// Issue 22 item 7: a new event time counts from its write, not from the
// next transmission. Written while the old, long timer runs, the next TPDO
// comes the new time after the write (before: when the old 1 s had run out,
// and only the one after it at the new period).
TEST_F(Tpdo, WritingTheEventTimerRestartsIt) {
  ASSERT_EQ(h.write_u16(0x1800, 5, 1000), 0u);  // ms
  h.nmt(0x01, kId);
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  h.run_us(300000, 1000);  // 300 ms into the 1 s
  EXPECT_EQ(h.take(), Frames({}));
  ASSERT_EQ(h.write_u16(0x1800, 5, 50), 0u);
  const uint32_t written = h.now;
  std::vector<uint32_t> at_us;
  for (int i = 0; i < 1600; ++i) {  // 160 ms in 100 us steps
    h.advance_us(100);
    if (!h.take().empty()) at_us.push_back(h.now - written);
  }
  EXPECT_EQ(at_us, std::vector<uint32_t>({50000, 100000, 150000}));
  // Longer again: the running 50 ms give way to the new 200 ms at once.
  h.run_us(20000, 1000);  // 30 ms into a 50 ms interval
  ASSERT_EQ(h.write_u16(0x1800, 5, 200), 0u);
  const uint32_t rewritten = h.now;
  at_us.clear();
  for (int i = 0; i < 4500; ++i) {  // 450 ms
    h.advance_us(100);
    if (!h.take().empty()) at_us.push_back(h.now - rewritten);
  }
  EXPECT_EQ(at_us, std::vector<uint32_t>({200000, 400000}));
}

TEST_F(Tpdo, RtrIsAnsweredUnlessBit30IsSet) {
  operational();
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x40000183u), 0u);
  h.rx(Rtr(0x183));
  h.rx(Rtr(0x183, 2));
  EXPECT_EQ(h.take(), Frames({}));
  // Event-driven transmission continues.
  io.set_input(0, 1);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 01 00"}));
}

TEST_F(Tpdo, RtrIsNotAnsweredOutsideOperationalOrWhenDisabled) {
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({}));
  operational();
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(Rtr(0x283));
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Tpdo, DataFramesOnTheTpdoIdAreIgnored) {
  operational();
  h.rx(F(0x183, {0x55, 0x66}));
  h.run_us(1000);
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_EQ(value(0x6000, 1), 0u);
}

TEST_F(Tpdo, AFullTransmitQueueIsRetriedLater) {
  operational();
  bus.refuse = true;
  const uint16_t failures = io.node().tpdos().send_failures();
  io.set_input(0, 0x77);
  h.run_us(1000);
  EXPECT_GT(io.node().tpdos().send_failures(), failures);
  bus.refuse = false;
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 77 00"}));
  h.run_us(1000);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Tpdo, ChangingTheCobIdMovesThePdo) {
  operational();
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x00000381u), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<381> 00 00"})) << "re-enabled: sends afresh";
  h.rx(Rtr(0x381));
  EXPECT_EQ(h.take(), Frames({"<381> 00 00"}));
  h.rx(Rtr(0x183));
  EXPECT_EQ(h.take(), Frames({}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
