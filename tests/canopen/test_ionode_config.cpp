// The I/O node's own node id and bit rate (2001h/1-2, issue 14: two of them
// on one bus): set by SDO, saved with 1010h in the node's two-slot storage,
// in force from the next reset; a power-on boots with the saved id at the
// saved rate. The same on the AVR image: tests/uno/test_uno_ionode.cpp.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "ionode/io_node.h"
#include "ram_storage.h"
#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

/// One board: the I/O node, its EEPROM (kept over power cycles) and its CAN
/// controller, which records the bit rates it is set to and when.
class IoNodeConfig : public ::testing::Test {
 protected:
  static constexpr uint8_t kDefaultId = 0x20;

  /// The bus and the CAN controller behind the sink: a port's CanControl
  /// gets the sink's ctx. Records the bit rates set and how many frames had
  /// left at the last one.
  struct Board : FrameLog {
    std::vector<uint16_t> rates;
    size_t frames_when_set = 0;
    static void set_bitrate(void* ctx, uint16_t kbit) {
      Board& b = *static_cast<Board*>(static_cast<FrameLog*>(ctx));
      b.rates.push_back(kbit);
      b.frames_when_set = b.frames.size();
    }
  };

  void SetUp() override { power_on(); }

  /// A fresh node on the same storage, as after a power cycle.
  void power_on() {
    h.reset();
    io.reset();
    bus.frames.clear();
    bus.rates.clear();
    io.reset(new ionode::IoNode(bus.sink()));
    io->node().set_storage(&api);
    io->node().set_can_control(&control);
    h.reset(new Harness(io->node(), bus));
    io->start(kDefaultId, h->now);
  }

  uint32_t save() {
    const uint32_t answer = h->write_u32(0x1010, 1, kSaveSignature);
    for (int pass = 0; pass < 100000 && io->node().saving(); ++pass) h->advance_us(100);
    EXPECT_FALSE(io->node().saving());
    return answer;
  }

  Board bus;
  const CanControl control = {&Board::set_bitrate, nullptr};
  RamStorage ram;
  ParamStorage api = ram.api();
  std::unique_ptr<ionode::IoNode> io;
  std::unique_ptr<Harness> h;
};

TEST_F(IoNodeConfig, AFreshBoardBootsWithTheDefaultIdAt500kbit) {
  EXPECT_EQ(bus.take(), Frames({"<720> 00"}));
  EXPECT_EQ(h->read(0x2001, 1), kDefaultId);
  EXPECT_EQ(h->read(0x2001, 2), 500u);
  ASSERT_EQ(bus.rates, std::vector<uint16_t>({500}));
  EXPECT_EQ(bus.frames_when_set, 0u) << "the rate is set before the boot-up message";
}

// The order docs/labs.md gives: the id, a reset communication (the COB-IDs
// of the pre-defined connection set follow the new id), then the save.
TEST_F(IoNodeConfig, ASavedIdAndRateAreThoseOfTheNextPowerOn) {
  bus.take();
  ASSERT_EQ(h->write_u8(0x2001, 1, 2), 0u);
  ASSERT_EQ(h->write_u16(0x2001, 2, 250), 0u);
  EXPECT_EQ(h->id(), kDefaultId) << "nothing changes before a reset";
  h->nmt(0x82, kDefaultId);
  EXPECT_EQ(bus.take(), Frames({"<702> 00"}));
  ASSERT_EQ(save(), 0u);
  power_on();
  EXPECT_EQ(bus.take(), Frames({"<702> 00"})) << "one boot-up, at the saved id";
  EXPECT_EQ(bus.rates, std::vector<uint16_t>({250}));
  EXPECT_EQ(bus.frames_when_set, 0u);
  EXPECT_EQ(h->read(0x2001, 1), 2u) << "SDO to 602h";
  EXPECT_EQ(h->read(0x1800, 1), 0x182u) << "node-id-relative COB-IDs follow";
  EXPECT_EQ(h->read(0x1400, 1), 0x202u);
}

// Issue 22 item 1: saved before any reset, the COB-IDs of the pre-defined
// connection set (180h + id, 200h + id, EMCY 80h + id) follow the id in
// force at the next power-on, as CANopenNode stores them; one set by a
// master to another value is kept as set.
TEST_F(IoNodeConfig, SavedBeforeTheResetTheCobIdsFollowTheNewId) {
  bus.take();
  ASSERT_EQ(h->write_u32(0x1801, 1, 0x2A5u), 0u) << "TPDO2 set by a master (and made valid)";
  ASSERT_EQ(h->write_u8(0x2001, 1, 2), 0u);
  ASSERT_EQ(save(), 0u);
  power_on();
  EXPECT_EQ(bus.take(), Frames({"<702> 00"}));
  EXPECT_EQ(h->read(0x1800, 1), 0x182u);
  EXPECT_EQ(h->read(0x1400, 1), 0x202u);
  EXPECT_EQ(h->read(0x1014, 0), 0x82u);
  EXPECT_EQ(h->read(0x1802, 1), 0x80000382u) << "not valid, and on the new id";
  EXPECT_EQ(h->read(0x1801, 1), 0x2A5u) << "a master's COB-ID stays";
  // And it goes on following: a new id, saved, power cycle.
  ASSERT_EQ(h->write_u8(0x2001, 1, 0x7F), 0u);
  ASSERT_EQ(save(), 0u);
  power_on();
  EXPECT_EQ(bus.take(), Frames({"<77F> 00"}));
  EXPECT_EQ(h->read(0x1800, 1), 0x1FFu);
  EXPECT_EQ(h->read(0x1014, 0), 0xFFu);
  EXPECT_EQ(h->read(0x1801, 1), 0x2A5u);
}

// A COB-ID a master set to the base of the pre-defined set itself (280h:
// node 0's TPDO2) is a COB-ID like any other: kept as set, not made relative
// (CANopenNode, storing the base alone, would move it to 280h + id).
TEST_F(IoNodeConfig, ACobIdSetToTheBaseItselfIsKeptAsSet) {
  ASSERT_EQ(h->write_u32(0x1801, 1, 0x280u), 0u);
  ASSERT_EQ(h->write_u8(0x2001, 1, 2), 0u);
  ASSERT_EQ(save(), 0u);
  power_on();
  EXPECT_EQ(h->read(0x1801, 1), 0x280u);
}

TEST_F(IoNodeConfig, AWrittenIdCountsFromTheNextResetCommunication) {
  bus.take();
  ASSERT_EQ(h->write_u8(0x2001, 1, 9), 0u);
  h->nmt(0x82, kDefaultId);
  EXPECT_EQ(bus.take(), Frames({"<709> 00"}));
  EXPECT_EQ(h->read(0x1800, 1), 0x189u);
}

// Issue 22 item 2: one boot-up, on the id in force (no phantom node 9).
TEST_F(IoNodeConfig, ResetNodeWithoutASavedSetGoesBackToThePowerOnId) {
  bus.take();
  ASSERT_EQ(h->write_u8(0x2001, 1, 9), 0u);
  h->nmt(0x81, kDefaultId);
  h->advance_us(100);
  EXPECT_EQ(bus.take(), Frames({"<720> 00"})) << "one boot-up, on the power-on id";
  EXPECT_EQ(h->read(0x1800, 1), 0x1A0u) << "the communication area is the power-on id's";
  EXPECT_EQ(h->id(), kDefaultId);
  EXPECT_EQ(h->read(0x2001, 1), kDefaultId);
}

TEST_F(IoNodeConfig, ResetNodeKeepsTheSavedIdAndRate) {
  ASSERT_EQ(h->write_u8(0x2001, 1, 5), 0u);
  ASSERT_EQ(h->write_u16(0x2001, 2, 1000), 0u);
  ASSERT_EQ(save(), 0u);
  bus.take();
  h->nmt(0x81, kDefaultId);
  h->advance_us(100);
  EXPECT_EQ(bus.take(), Frames({"<705> 00"})) << "one boot-up, on the saved id";
  EXPECT_EQ(bus.rates.back(), 1000u);
}

TEST_F(IoNodeConfig, IdsAndRatesOutsideTheChipsTableAreRefused) {
  EXPECT_EQ(h->write_u8(0x2001, 1, 0), uint32_t{kAbortValueTooLow});
  EXPECT_EQ(h->write_u8(0x2001, 1, 128), uint32_t{kAbortValueTooHigh});
  EXPECT_EQ(h->write_u16(0x2001, 2, 100), uint32_t{kAbortValueTooLow});
  for (uint32_t kbit : {200u, 300u, 800u}) {
    EXPECT_EQ(h->write_u16(0x2001, 2, kbit), uint32_t{kAbortInvalidValue}) << kbit;
  }
  EXPECT_EQ(h->write_u16(0x2001, 2, 1001), uint32_t{kAbortValueTooHigh});
  for (uint32_t kbit : {125u, 250u, 500u, 1000u}) EXPECT_EQ(h->write_u16(0x2001, 2, kbit), 0u) << kbit;
  EXPECT_EQ(h->read(0x2001, 1), kDefaultId);
}

TEST_F(IoNodeConfig, RestoringDefaultsBringsTheDefaultIdBackAtTheNextPowerOn) {
  ASSERT_EQ(h->write_u8(0x2001, 1, 7), 0u);
  ASSERT_EQ(save(), 0u);
  ASSERT_EQ(h->write_u32(0x1011, 1, kLoadSignature), 0u);
  power_on();
  EXPECT_EQ(bus.take(), Frames({"<720> 00"}));
  EXPECT_EQ(bus.rates, std::vector<uint16_t>({500}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
