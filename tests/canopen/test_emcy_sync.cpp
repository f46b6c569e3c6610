// EMCY producer (CiA 301 §7.2.7: 1001h, 1003h, 1014h, 1015h) and SYNC
// consumer/producer (§7.2.5: 1005h, 1006h, 1019h).
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Emcy = IoNodeTest;

TEST_F(Emcy, FrameCarriesCodeRegisterAndManufacturerField) {
  const uint8_t info[5] = {0xA1, 0xB2, 0xC3, 0xD4, 0xE5};
  io.node().emcy().raise(0x4210, kErrTemperature, info);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({"<083> 10 42 09 A1 B2 C3 D4 E5"}));
  EXPECT_EQ(h.read(0x1001, 0), 0x09u);
  EXPECT_EQ(h.read(0x1003, 0), 1u);
  EXPECT_EQ(h.read(0x1003, 1), 0xB2A14210u) << "first two info bytes in the upper half";
}

TEST_F(Emcy, OneFramePerAppearanceAndErrorResetWhenTheLastClears) {
  EmcyProducer& e = io.node().emcy();
  e.raise(0x5000, kErrDeviceProfile);
  e.raise(0x5000, kErrDeviceProfile);  // already active: nothing new
  h.advance_us(10);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({"<083> 00 50 21 00 00 00 00 00"}));
  e.raise(0x3100, kErrVoltage);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({"<083> 00 31 25 00 00 00 00 00"}));
  e.clear(0x5000);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({})) << "0x3100 is still active";
  EXPECT_EQ(h.read(0x1001, 0), 0x05u);
  e.clear(0x5000);  // not active any more: nothing
  e.clear(0x3100);
  h.advance_us(10);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1001, 0), 0u);
  EXPECT_FALSE(e.active(0x3100));
  // The history keeps the errors (not the resets).
  EXPECT_EQ(h.read(0x1003, 0), 2u);
  EXPECT_EQ(h.read(0x1003, 1), 0x3100u);
  EXPECT_EQ(h.read(0x1003, 2), 0x5000u);
}

TEST_F(Emcy, HistoryIsNewestFirstAndKeepsTheLastFour) {
  EmcyProducer& e = io.node().emcy();
  const uint16_t codes[] = {0x1000, 0x2000, 0x3000, 0x4000, 0x5000, 0x6000};
  for (uint16_t c : codes) {
    e.raise(c, kErrGeneric);
    h.advance_us(10);
    EXPECT_EQ(h.read(0x1003, 1), c);
  }
  EXPECT_EQ(h.read(0x1003, 0), 4u);
  EXPECT_EQ(h.read(0x1003, 1), 0x6000u);
  EXPECT_EQ(h.read(0x1003, 2), 0x5000u);
  EXPECT_EQ(h.read(0x1003, 3), 0x4000u);
  EXPECT_EQ(h.read(0x1003, 4), 0x3000u);
  // Writing 0 to sub 0 deletes the history.
  ASSERT_EQ(h.write_u8(0x1003, 0, 0), 0u);
  EXPECT_EQ(h.read(0x1003, 0), 0u);
  for (uint8_t s = 1; s <= 4; ++s) EXPECT_EQ(h.read(0x1003, s), 0u);
  // The error register is not the history: errors are still active.
  EXPECT_EQ(h.read(0x1001, 0), 0x01u);
  e.raise(0x7000, kErrGeneric);
  EXPECT_EQ(h.read(0x1003, 0), 1u);
  EXPECT_EQ(h.read(0x1003, 1), 0x7000u);
}

TEST_F(Emcy, InhibitTimeSpacesMessagesIn100MicrosecondUnits) {
  ASSERT_EQ(h.write_u16(0x1015, 0, 50), 0u);  // 5 ms
  EmcyProducer& e = io.node().emcy();
  e.raise(0x1000, kErrGeneric);
  e.raise(0x2000, kErrCurrent);
  e.clear(0x1000);
  e.clear(0x2000);
  h.advance_us(1);
  EXPECT_EQ(h.take(), Frames({"<083> 00 10 01 00 00 00 00 00"}));
  h.run_us(4999, 1);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1);  // 5000 µs after the first
  EXPECT_EQ(h.take(), Frames({"<083> 00 20 03 00 00 00 00 00"}));
  h.run_us(4999, 1);
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(1);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
}

TEST_F(Emcy, QueueOverflowIsCountedAndTheRestArrives) {
  ASSERT_EQ(h.write_u16(0x1015, 0, 10), 0u);  // 1 ms
  EmcyProducer& e = io.node().emcy();
  for (uint16_t c = 1; c <= 6; ++c) e.raise(static_cast<uint16_t>(0x1000 + c), kErrGeneric);
  EXPECT_EQ(e.overflows(), 2u);
  h.run_us(10000, 100);
  EXPECT_EQ(h.take(), Frames({"<083> 01 10 01 00 00 00 00 00", "<083> 02 10 01 00 00 00 00 00",
                              "<083> 03 10 01 00 00 00 00 00", "<083> 04 10 01 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1003, 1), 0x1006u) << "the history has them all";
}

TEST_F(Emcy, AFullTransmitQueueIsRetried) {
  bus.refuse = true;
  io.node().emcy().raise(0x5000, kErrDeviceProfile);
  h.run_us(1000);
  bus.refuse = false;
  EXPECT_EQ(h.take(), Frames({}));
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<083> 00 50 21 00 00 00 00 00"}));
}

TEST_F(Emcy, CobIdChangesOnlyThroughInvalidAndInvalidSendsNothing) {
  ASSERT_EQ(h.write_u32(0x1014, 0, 0x80000083u), 0u);
  io.node().emcy().raise(0x5000, kErrDeviceProfile);
  h.run_us(1000);
  EXPECT_EQ(h.take(), Frames({}));
  ASSERT_EQ(h.write_u32(0x1014, 0, 0x000000A0u), 0u);
  io.node().emcy().clear(0x5000);
  io.node().emcy().raise(0x6000, kErrGeneric);
  h.advance_us(100);  // one EMCY per process() call
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<0A0> 00 00 00 00 00 00 00 00", "<0A0> 00 60 01 00 00 00 00 00"}));
}

// ---- SYNC ------------------------------------------------------------------------
using Sync = IoNodeTest;

/// TPDO1 (inputs) synchronous every `n` SYNCs, operational.
void sync_tpdo(Harness& h, uint8_t type) {
  ASSERT_EQ(h.write_u8(0x1800, 2, type), 0u);
  h.nmt(0x01, h.id());
  h.take();
}

TEST_F(Sync, ConsumerTriggersSynchronousPdos) {
  sync_tpdo(h, 1);
  io.set_input(0, 0x42);
  h.run_us(10000);
  EXPECT_EQ(h.take(), Frames({})) << "synchronous: waits for the SYNC";
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 42 00"}));
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 42 00"})) << "type 1: every SYNC, changed or not";
}

TEST_F(Sync, ConsumerFollowsTheCobId) {
  sync_tpdo(h, 1);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x90u), 0u);
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(F(0x090, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 00 00"}));
}

TEST_F(Sync, ProducerSendsEveryPeriod) {
  ASSERT_EQ(h.write_u32(0x1006, 0, 10000u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  h.run_us(35000, 100);
  EXPECT_EQ(h.take(), Frames({"<080>", "<080>", "<080>"})) << "pre-operational produces SYNC";
  // Its own SYNC drives its synchronous PDOs.
  sync_tpdo(h, 1);
  h.run_us(10000, 100);
  EXPECT_EQ(h.take(), Frames({"<080>", "<183> 00 00"}));
  // Stopped: no SYNC.
  h.nmt(0x02, kId);
  h.run_us(50000, 100);
  EXPECT_EQ(h.take(), Frames({}));
  // The id cannot change while producing; clearing bit 30 stops it.
  h.nmt(0x80, kId);
  h.take();
  h.expect_abort({0x23, 0x05, 0x10, 0x00, 0x90, 0x00, 0x00, 0x40}, 0x1005, 0, kAbortInvalidValue);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x80u), 0u);
  h.run_us(50000, 100);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Sync, ProducerTimingIsExactAndRestartsOnWrite) {
  ASSERT_EQ(h.write_u32(0x1006, 0, 2500u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  uint32_t start = h.now;
  std::vector<uint32_t> at;
  for (int i = 0; i < 10000; ++i) {
    h.advance_us(1);
    for (const CanFrame& f : h.take_frames()) {
      if (f.id == 0x80) at.push_back(h.now - start);
    }
  }
  EXPECT_EQ(at, std::vector<uint32_t>({2500, 5000, 7500, 10000}));
  ASSERT_EQ(h.write_u32(0x1006, 0, 1000u), 0u);
  start = h.now;
  at.clear();
  for (int i = 0; i < 3000; ++i) {
    h.advance_us(1);
    for (const CanFrame& f : h.take_frames()) {
      if (f.id == 0x80) at.push_back(h.now - start);
    }
  }
  EXPECT_EQ(at, std::vector<uint32_t>({1000, 2000, 3000}));
}

TEST_F(Sync, CounterRunsFromOneToTheOverflowValue) {
  ASSERT_EQ(h.write_u8(0x1019, 0, 3), 0u);
  ASSERT_EQ(h.write_u32(0x1006, 0, 1000u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  h.run_us(7000, 100);
  EXPECT_EQ(h.take(),
            Frames({"<080> 01", "<080> 02", "<080> 03", "<080> 01", "<080> 02", "<080> 03", "<080> 01"}));
}

TEST_F(Sync, CounterOf240Wraps) {
  ASSERT_EQ(h.write_u8(0x1019, 0, 240), 0u);
  ASSERT_EQ(h.write_u32(0x1006, 0, 100u), 0u);
  ASSERT_EQ(h.write_u32(0x1005, 0, 0x40000080u), 0u);
  h.run_us(24200, 100);
  const std::vector<CanFrame> f = h.take_frames();
  ASSERT_EQ(f.size(), 242u);
  for (size_t i = 0; i < f.size(); ++i) {
    ASSERT_EQ(f[i].dlc, 1);
    EXPECT_EQ(f[i].data[0], i % 240 + 1);
  }
}

TEST_F(Sync, SyncStartValueDelaysTheFirstCyclicTransmission) {
  ASSERT_EQ(h.write_u8(0x1019, 0, 5), 0u);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ASSERT_EQ(h.write_u8(0x1800, 6, 3), 0u);
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x183u), 0u);
  sync_tpdo(h, 2);
  std::vector<uint8_t> sent_at;
  for (uint8_t round = 0; round < 3; ++round) {
    for (uint8_t c = 1; c <= 5; ++c) {
      h.rx(F(0x080, {c}));
      if (!h.take().empty()) sent_at.push_back(c);
    }
  }
  // First at counter 3, then every 2nd SYNC: 3, 5, 2, 4, 1, 3, 5.
  EXPECT_EQ(sent_at, std::vector<uint8_t>({3, 5, 2, 4, 1, 3, 5}));
}

TEST_F(Sync, WrongLengthRaisesEmcy8240AndIsNoSync) {
  sync_tpdo(h, 1);
  h.rx(F(0x080, {0x01}));  // 1019h = 0: a SYNC has no data
  EXPECT_EQ(h.take(), Frames({"<083> 40 82 11 00 00 00 00 00"}));
  for (uint8_t dlc = 1; dlc <= 8; ++dlc) {
    CanFrame f = F(0x080, {1, 2, 3, 4, 5, 6, 7, 8});
    f.dlc = dlc;
    h.rx(f);
  }
  EXPECT_EQ(h.take(), Frames({})) << "one EMCY while the error lasts; no PDO";
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<183> 00 00", "<083> 00 00 00 00 00 00 00 00"}));
  // With a counter, a SYNC without one is wrong.
  h.nmt(0x80, kId);
  ASSERT_EQ(h.write_u8(0x1019, 0, 10), 0u);
  h.rx(F(0x080, {}));
  EXPECT_EQ(h.take(), Frames({"<083> 40 82 11 00 00 00 00 00"}));
  h.rx(F(0x080, {0x01, 0x00}));
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(F(0x080, {0x01}));
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
}

TEST_F(Sync, RtrOnTheSyncIdIsIgnored) {
  sync_tpdo(h, 1);
  h.rx(Rtr(0x080));
  h.rx(Rtr(0x080, 1));
  EXPECT_EQ(h.take(), Frames({}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
