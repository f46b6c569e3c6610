// The SocketCAN port's frame mapping and argument checks: no CAN interface
// needed, runs on any host (the vcan tests cover the kernel side).
#include <gtest/gtest.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <string.h>

#include "can_text.h"
#include "platform/socketcan_port.h"

namespace {

using mb2co::CanFrame;
using mb2co::linux_port::from_kernel_frame;
using mb2co::linux_port::SocketCanPort;
using mb2co::linux_port::to_kernel_frame;
using mb2co::test::from_text;
using mb2co::test::make_frame;
using mb2co::test::same_frame;
using mb2co::test::to_text;

can_frame kernel_of(const CanFrame& f) {
  can_frame k;
  memset(&k, 0xEE, sizeof k);  // show which bytes the conversion writes
  EXPECT_TRUE(to_kernel_frame(f, k)) << to_text(f);
  return k;
}

TEST(SocketCanCodec, StandardDataFrame) {
  const can_frame k = kernel_of(make_frame(0x123, 0, 3, "112233"));
  EXPECT_EQ(k.can_id, 0x123u);
  EXPECT_EQ(k.len, 3u);
  const uint8_t expected[8] = {0x11, 0x22, 0x33, 0, 0, 0, 0, 0};  // beyond dlc zeroed
  EXPECT_EQ(memcmp(k.data, expected, 8), 0);
}

TEST(SocketCanCodec, ExtendedAndRtrFlagsMapToIdBits) {
  EXPECT_EQ(kernel_of(make_frame(0x1FFFFFFF, CanFrame::kExtended, 0)).can_id, 0x1FFFFFFFu | CAN_EFF_FLAG);
  EXPECT_EQ(kernel_of(make_frame(0x001, CanFrame::kExtended, 0)).can_id, 0x001u | CAN_EFF_FLAG);
  const can_frame rtr = kernel_of(make_frame(0x456, CanFrame::kRtr, 5));
  EXPECT_EQ(rtr.can_id, 0x456u | CAN_RTR_FLAG);
  EXPECT_EQ(rtr.len, 5u);  // an RTR frame carries the dlc it asks for
  const can_frame both = kernel_of(make_frame(0x1234567, CanFrame::kRtr | CanFrame::kExtended, 8));
  EXPECT_EQ(both.can_id, 0x1234567u | CAN_EFF_FLAG | CAN_RTR_FLAG);
}

TEST(SocketCanCodec, RefusesFramesThatDoNotFitTheirFormat) {
  can_frame k{};
  CanFrame f = make_frame(0x800, 0, 0);  // 12 bits in a standard id
  EXPECT_FALSE(to_kernel_frame(f, k));
  f = make_frame(0x20000000, CanFrame::kExtended, 0);  // 30 bits
  EXPECT_FALSE(to_kernel_frame(f, k));
  f = make_frame(0x100, 0, 8);
  f.dlc = 9;
  EXPECT_FALSE(to_kernel_frame(f, k));
}

TEST(SocketCanCodec, KernelFramesComeBackUnchanged) {
  for (const char* text : {"000#", "123#1122334455667788", "7FF#A1", "1FFFFFFF#0102", "00000001#AA", "456#R",
                           "181#R8", "01234567#R3"}) {
    CanFrame in{};
    ASSERT_TRUE(from_text(text, in)) << text;
    const can_frame k = kernel_of(in);
    CanFrame out;
    memset(&out, 0xEE, sizeof out);
    ASSERT_TRUE(from_kernel_frame(k, out)) << text;
    EXPECT_TRUE(same_frame(in, out)) << text << " came back as " << to_text(out);
    EXPECT_EQ(to_text(out), text);
    for (unsigned i = out.rtr() ? 0 : out.dlc; i < 8; ++i) EXPECT_EQ(out.data[i], 0) << text << " byte " << i;
  }
}

TEST(SocketCanCodec, ErrorFramesAndLongLengthsAreNotFrames) {
  can_frame k{};
  CanFrame out{};
  k.can_id = CAN_ERR_FLAG | CAN_ERR_BUSOFF;
  k.len = 8;
  EXPECT_FALSE(from_kernel_frame(k, out));
  k.can_id = 0x123;
  k.len = 9;
  EXPECT_FALSE(from_kernel_frame(k, out));
}

TEST(SocketCanCodec, TextNotationRejectsMalformedInput) {
  CanFrame f{};
  for (const char* bad :
       {"", "123", "12#00", "123#R9", "123#123", "12345#00", "123#001122334455667788", "XYZ#"}) {
    EXPECT_FALSE(from_text(bad, f)) << bad;
  }
}

TEST(SocketCanPortArguments, BadNamesFailBeforeTheKernelIsAsked) {
  SocketCanPort port;
  const mb2co::Status empty = port.open("");
  EXPECT_FALSE(empty);
  EXPECT_NE(strstr(empty.message().c_str(), "interface name"), nullptr) << empty.message();
  const mb2co::Status too_long = port.open("a_name_of_16_chr");
  EXPECT_FALSE(too_long);
  EXPECT_NE(strstr(too_long.message().c_str(), "interface name"), nullptr) << too_long.message();
  EXPECT_FALSE(port.open(nullptr));
  EXPECT_FALSE(port.is_open());
}

TEST(SocketCanPortArguments, ClosedPortRefusesAndCounts) {
  SocketCanPort port;
  EXPECT_FALSE(port.send(make_frame(0x100, 0, 0)));
  EXPECT_EQ(port.counters().tx_errors, 1u);
  EXPECT_FALSE(port.set_filters(nullptr, 0));
  mb2co::linux_port::TimedCanFrame any;
  EXPECT_FALSE(port.receive(any));
}

}  // namespace
