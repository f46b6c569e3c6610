// The I/O node's CiA 401 input parameters, black box over SDO and the bus:
// the polarity 6002h inverts what 6000h reads, and the global interrupt
// enable 6005h with the masks 6006h (any change), 6007h (low-to-high) and
// 6008h (high-to-low) decide which changes send TPDO1 (type 255, the device
// profile's event); the event timer still sends the inputs as they are.
// The same objects on the AVR image, read by npm's canopen: tests/peers.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using Cia401Inputs = IoNodeTest;

TEST_F(Cia401Inputs, DefaultsAreCiA401s) {
  EXPECT_EQ(h.read(0x6002, 0), 2u);
  EXPECT_EQ(h.read(0x6002, 1), 0x00u) << "not inverted";
  EXPECT_EQ(h.read(0x6005, 0), 1u) << "interrupts enabled";
  EXPECT_EQ(h.read(0x6006, 1), 0xFFu) << "any change of any bit";
  EXPECT_EQ(h.read(0x6006, 2), 0xFFu);
  EXPECT_EQ(h.read(0x6007, 1), 0x00u);
  EXPECT_EQ(h.read(0x6008, 2), 0x00u);
}

TEST_F(Cia401Inputs, PolarityInvertsTheReadInputs) {
  operational();
  io.set_input(0, 0x0F);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 0F 00"}));
  // Inverting bits 0 and 7 of input 1 changes what 6000h/1 reads at once,
  // and that change is published like one of the pins.
  ASSERT_EQ(h.write_u8(0x6002, 1, 0x81), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.read(0x6000, 1), 0x8Eu);
  EXPECT_EQ(h.take(), Frames({"<183> 8E 00"}));
  io.set_input(1, 0x01);
  ASSERT_EQ(h.write_u8(0x6002, 2, 0xFF), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.read(0x6000, 2), 0xFEu);
  io.set_input(0, 0x00);
  h.advance_us(100);
  EXPECT_EQ(h.read(0x6000, 1), 0x81u) << "the pins low, the inverted bits read 1";
}

TEST_F(Cia401Inputs, MasksDecideWhichChangesSendTpdo1) {
  operational();
  // Bit 0 on any change, bit 1 only rising, bit 2 only falling, the rest never.
  ASSERT_EQ(h.write_u8(0x6006, 1, 0x01), 0u);
  ASSERT_EQ(h.write_u8(0x6007, 1, 0x02), 0u);
  ASSERT_EQ(h.write_u8(0x6008, 1, 0x04), 0u);
  h.take();
  struct Step {
    uint8_t pins;
    bool sends;
  } const steps[] = {
      {0x01, true},   // bit 0 rises: any change
      {0x00, true},   // bit 0 falls: any change
      {0x02, true},   // bit 1 rises
      {0x00, false},  // bit 1 falls: not in 6008h
      {0x04, false},  // bit 2 rises: not in 6007h
      {0x00, true},   // bit 2 falls
      {0x08, false},  // bit 3: in no mask
  };
  for (const Step& s : steps) {
    io.set_input(0, s.pins);
    h.advance_us(100);
    EXPECT_EQ(h.read(0x6000, 1), s.pins) << "6000h follows the pins whatever the masks";
    char want[32];
    std::snprintf(want, sizeof want, "<183> %02X 00", s.pins);
    EXPECT_EQ(h.take(), s.sends ? Frames({want}) : Frames({})) << "pins " << unsigned(s.pins);
  }
  // An unrelated write changes the OD: a masked change still does not go out.
  ASSERT_EQ(h.write_u16(0x2101, 0, 20), 0u);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({}));
  // The next event carries every input as it is.
  io.set_input(0, 0x09);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 09 00"}));
}

TEST_F(Cia401Inputs, GlobalInterruptDisabledLeavesTheEventTimer) {
  ASSERT_EQ(h.write_u8(0x6005, 0, 0), 0u);
  operational();
  h.take();
  io.set_input(0, 0x33);
  h.run_us(50000);
  EXPECT_EQ(h.take(), Frames({})) << "no interrupt: the change is not sent";
  EXPECT_EQ(h.read(0x6000, 1), 0x33u);
  // The event timer (100 ms) sends the inputs as they are.
  ASSERT_EQ(h.write_u16(0x1800, 5, 100), 0u);
  h.take();
  h.run_us(100000);
  EXPECT_EQ(h.take(), Frames({"<183> 33 00"}));
  // Enabled again: the next change goes out at once.
  ASSERT_EQ(h.write_u8(0x6005, 0, 1), 0u);
  io.set_input(0, 0x30);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 30 00"}));
}

TEST_F(Cia401Inputs, Type254SendsEveryChangeWhateverTheMasks) {
  ASSERT_EQ(h.write_u8(0x6006, 1, 0x00), 0u);
  ASSERT_EQ(h.write_u8(0x1800, 2, 254), 0u);
  operational();
  h.take();
  io.set_input(0, 0x10);
  h.advance_us(100);
  EXPECT_EQ(h.take(), Frames({"<183> 10 00"}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
