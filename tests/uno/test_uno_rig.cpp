// The simulated Uno with a real image on its MCP2515: firmware/avr's
// mcp2515-echo (every frame received goes back with id + 1) run in
// UnoRig. Shows the SPI unit at the real Uno's speed (F_CPU/2: 1 µs a byte,
// where simavr alone takes 100 µs) and the INT pin, through the driver's
// real traffic: the echo leaves within a few hundred µs of the frame's end.
#include <gtest/gtest.h>

#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

TEST(UnoRig, EchoImageAnswersAFrameWithinMicroseconds) {
  UnoRig rig;
  const Status loaded = rig.load(MB2CO_UNO_ECHO_ELF);
  ASSERT_TRUE(loaded) << loaded.message();
  ASSERT_TRUE(rig.run_until_us(300000));  // set-up: chip reset, 500 kbit/s, normal mode
  ASSERT_EQ(rig.take_can_out().size(), 0u);
  CanFrame in{};
  in.id = 0x123;
  in.dlc = 1;
  in.data[0] = 0x11;
  const uint64_t sent_at_us = rig.now_us();
  rig.can_in(in);
  ASSERT_TRUE(rig.run_until_us(sent_at_us + 20000));
  const auto out = rig.take_can_out();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].frame.id, 0x124u);
  ASSERT_EQ(out[0].frame.dlc, 1);
  EXPECT_EQ(out[0].frame.data[0], 0x11);
  // 123#11 is 55 bits incl. stuffing and IFS (110 µs at 500 kbit/s), as is
  // the echo; in between the image reads the frame and loads the answer:
  // ~40 SPI bytes, a few hundred µs with 1 µs bytes, > 4 ms with 100 µs ones.
  const uint64_t turnaround_us = out[0].end_cycle / 16 - sent_at_us;
  EXPECT_LT(turnaround_us, 1000u);
  EXPECT_GT(turnaround_us, 220u) << "two frames on the wire take at least their bits";
  RecordProperty("echo_turnaround_us", static_cast<int>(turnaround_us));
  printf("echo turnaround %llu us\n", static_cast<unsigned long long>(turnaround_us));
}

}  // namespace
}  // namespace uno
}  // namespace mb2co
