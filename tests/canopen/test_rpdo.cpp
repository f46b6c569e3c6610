// Receive PDOs (CiA 301 §7.2.2): immediate and synchronous application,
// event-timer timeout (EMCY 8250h), length errors (8210h short: dropped,
// 8220h long: applied), RTR, disabled PDOs and dynamic mapping.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

class Rpdo : public IoNodeTest {
 protected:
  void SetUp() override {
    IoNodeTest::SetUp();
    io.node().rpdos().set_callback(&Rpdo::on_rpdo, this);
  }
  static void on_rpdo(void* ctx, uint8_t n) { static_cast<Rpdo*>(ctx)->applied.push_back(n); }
  std::vector<uint8_t> applied;
};

TEST_F(Rpdo, Type255IsAppliedOnReception) {
  operational();
  h.rx(F(0x203, {0x12, 0x34}));
  EXPECT_EQ(io.output(0), 0x12);
  EXPECT_EQ(io.output(1), 0x34);
  EXPECT_EQ(applied, std::vector<uint8_t>({0}));
  EXPECT_EQ(h.take(), Frames({}));
}

// An output under local control (2100h) refuses the network: an SDO write
// gets 08000021h (SdoAbort.OutputsUnderLocalControl_08000021), an RPDO is
// not applied either; back under network control the next RPDO is.
TEST_F(Rpdo, OutputsUnderLocalControlIgnoreTheRpdo) {
  operational();
  h.rx(F(0x203, {0x12, 0x34}));
  ASSERT_EQ(io.output(0), 0x12);
  ASSERT_EQ(h.write_u8(0x2100, 0, 1), 0u);
  h.rx(F(0x203, {0x56, 0x78}));
  EXPECT_EQ(io.output(0), 0x12);
  EXPECT_EQ(io.output(1), 0x34);
  ASSERT_EQ(h.write_u8(0x2100, 0, 0), 0u);
  h.rx(F(0x203, {0x56, 0x78}));
  EXPECT_EQ(io.output(0), 0x56);
  EXPECT_EQ(io.output(1), 0x78);
  EXPECT_EQ(h.take(), Frames({})) << "an RPDO is never answered, refused or not";
}

TEST_F(Rpdo, SynchronousTypesAreAppliedAtTheNextSync) {
  ASSERT_EQ(h.write_u8(0x1400, 2, 1), 0u);
  operational();
  h.rx(F(0x203, {0x01, 0x02}));
  h.rx(F(0x203, {0x03, 0x04}));  // the last one before the SYNC counts
  h.run_us(10000);
  EXPECT_EQ(io.output(0), 0);
  EXPECT_TRUE(applied.empty());
  h.rx(F(0x080, {}));
  EXPECT_EQ(io.output(0), 0x03);
  EXPECT_EQ(io.output(1), 0x04);
  EXPECT_EQ(applied, std::vector<uint8_t>({0}));
  h.rx(F(0x080, {}));
  EXPECT_EQ(applied.size(), 1u) << "applied once";
  // Type 0 and 240 are synchronous too.
  for (const uint8_t type : std::vector<uint8_t>{0, 240}) {
    h.nmt(0x80, kId);
    ASSERT_EQ(h.write_u8(0x1400, 2, type), 0u);
    operational();
    h.rx(F(0x203, {type, type}));
    EXPECT_NE(io.output(0), type);
    h.rx(F(0x080, {}));
    EXPECT_EQ(io.output(0), type);
  }
}

TEST_F(Rpdo, LeavingOperationalDropsABufferedSynchronousPdo) {
  ASSERT_EQ(h.write_u8(0x1400, 2, 1), 0u);
  operational();
  h.rx(F(0x203, {0x01, 0x02}));
  h.nmt(0x80, kId);
  operational();
  h.rx(F(0x080, {}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_TRUE(applied.empty());
}

TEST_F(Rpdo, NotAppliedOutsideOperational) {
  h.rx(F(0x203, {0x01, 0x02}));
  EXPECT_EQ(io.output(0), 0);
  h.nmt(0x02, kId);
  h.rx(F(0x203, {0x01, 0x02}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_TRUE(applied.empty());
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Rpdo, EventTimerTimeoutRaisesEmcy8250) {
  ASSERT_EQ(h.write_u16(0x1400, 5, 100), 0u);  // ms
  operational();
  h.run_us(1000000, 1000);
  EXPECT_EQ(h.take(), Frames({})) << "monitoring starts with the first reception";
  h.rx(F(0x203, {0x01, 0x02}));
  h.run_us(99000, 1000);
  h.rx(F(0x203, {0x01, 0x03}));  // in time: restarts the timer
  h.run_us(99000, 1000);
  EXPECT_EQ(h.take(), Frames({}));
  h.run_us(1000, 100);
  EXPECT_EQ(h.take(), Frames({"<083> 50 82 11 00 00 00 00 00"}));
  EXPECT_EQ(h.read(0x1003, 1), 0x8250u);
  h.run_us(500000, 1000);
  EXPECT_EQ(h.take(), Frames({})) << "once";
  h.rx(F(0x203, {0x01, 0x04}));
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
  EXPECT_EQ(io.output(1), 0x04);
}

TEST_F(Rpdo, TooShortRaisesEmcy8210AndIsNotApplied) {
  operational();
  h.rx(F(0x203, {0x01}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_TRUE(applied.empty());
  EXPECT_EQ(h.take(), Frames({"<083> 10 82 11 00 00 00 00 00"}));
  h.rx(F(0x203, {}));
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(F(0x203, {0x05, 0x06}));
  EXPECT_EQ(io.output(0), 0x05);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
}

TEST_F(Rpdo, TooLongRaisesEmcy8220AndIsApplied) {
  operational();
  h.rx(F(0x203, {0x07, 0x08, 0x09}));
  EXPECT_EQ(io.output(0), 0x07);
  EXPECT_EQ(io.output(1), 0x08);
  EXPECT_EQ(h.take(), Frames({"<083> 20 82 11 00 00 00 00 00"}));
  h.rx(F(0x203, {1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_EQ(io.output(0), 0x01);
  EXPECT_EQ(h.take(), Frames({}));
  h.rx(F(0x203, {0x05, 0x06}));
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"}));
}

TEST_F(Rpdo, RtrOnAnRpdoIdIsIgnored) {
  operational();
  h.rx(Rtr(0x203));
  h.rx(Rtr(0x203, 2));
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_TRUE(applied.empty());
}

TEST_F(Rpdo, DisabledRpdoIgnoresItsFrames) {
  operational();
  ASSERT_EQ(h.write_u32(0x1400, 1, 0x80000203u), 0u);
  h.rx(F(0x203, {0x01, 0x02}));
  h.rx(F(0x203, {0x01}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_EQ(h.take(), Frames({})) << "no length error for a PDO that does not exist";
  h.rx(F(0x303, {0x01, 0x02}));  // RPDO2, disabled by default
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(Rpdo, DynamicMappingOfRpdo2) {
  ASSERT_EQ(h.write_u8(0x1601, 0, 0), 0u);
  ASSERT_EQ(h.write_u32(0x1601, 1, 0x00050008u), 0u);  // skip a byte
  ASSERT_EQ(h.write_u32(0x1601, 2, 0x62000208u), 0u);
  ASSERT_EQ(h.write_u8(0x1601, 0, 2), 0u);
  ASSERT_EQ(h.write_u32(0x1401, 1, 0x00000303u), 0u);
  operational();
  h.rx(F(0x303, {0xEE, 0x42}));
  EXPECT_EQ(io.output(0), 0);
  EXPECT_EQ(io.output(1), 0x42);
  EXPECT_EQ(applied, std::vector<uint8_t>({1}));
  // RPDO1 and RPDO2 can share nothing but the node: both work.
  h.rx(F(0x203, {0x11, 0x22}));
  EXPECT_EQ(io.output(0), 0x11);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
