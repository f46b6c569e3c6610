// The remote-read latency of docs/gateway-network.md, against the numbers
// worked out there by hand.
#include <gtest/gtest.h>

#include "timing/remote_read.h"

namespace mb2co {
namespace timing {
namespace {

SerialFormat fast_line() {
  SerialFormat f;
  f.baud = 115200;
  f.parity = modbus::Parity::kEven;
  return f;
}

TEST(RemoteRead, FrameSizesAndSteps) {
  EXPECT_EQ(net_upload_exchange(4).request_bytes, 15u);
  EXPECT_EQ(net_upload_exchange(4).response_bytes, 23u);
  EXPECT_EQ(sdo_upload_steps(4).frames, 2u);
  EXPECT_EQ(sdo_upload_steps(4).answers, 1u);
  EXPECT_EQ(sdo_upload_steps(13).frames, 6u) << "initiate + 2 segments, both ways";
  EXPECT_EQ(sdo_upload_steps(13).answers, 3u);
  EXPECT_EQ(sdo_upload_steps(14).frames, 6u);
  EXPECT_EQ(sdo_upload_steps(15).frames, 8u);
}

TEST(RemoteRead, ExpeditedReadAt115200And500k) {
  const RemoteReadTiming t = remote_read_timing(fast_line(), 500000, 4, 4, 0, 0, WorstCase::kDavis);
  // (15 + 23) x 11 bits / 115200 = 3.628 ms, + t3.5 1.75 ms.
  EXPECT_EQ(t.serial_ns, 3628473u + 1750000u);
  // Two 8-byte frames: 111 bits unstuffed, 135 with worst stuffing.
  EXPECT_EQ(t.can_best_ns, 2u * 111u * 2000u);
  EXPECT_EQ(t.can_worst_ns, 2u * 135u * 2000u);
  EXPECT_NEAR(static_cast<double>(t.worst_ns), 5.9e6, 0.05e6) << "the doc's 5.9 ms + T_node";
  EXPECT_LT(t.best_ns, t.worst_ns);
}

TEST(RemoteRead, NodeAndGatewayTimesCountPerAnswer) {
  const RemoteReadTiming base = remote_read_timing(fast_line(), 500000, 13, 13, 0, 0, WorstCase::kDavis);
  const RemoteReadTiming slow =
      remote_read_timing(fast_line(), 500000, 13, 13, 1000000, 100000, WorstCase::kDavis);
  EXPECT_EQ(slow.worst_ns - base.worst_ns, 3u * 1000000u + 4u * 100000u);
  EXPECT_NEAR(static_cast<double>(base.worst_ns), 7.9e6, 0.1e6) << "the doc's 7.9 ms + 3 T_node";
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
