// One clock for a transfer's time (issue 22 item 5): `uploaded 4 bytes ...
// in 4294.967 s` came from a transfer started at a pass of the bus loop
// (the monotonic clock) and ended by a frame whose kernel receive time,
// shifted from the wall clock with two clock reads, lay a few µs before that
// pass. The loop hands its services one ServiceClock; these tests feed it
// exactly such a receive time and drive the master's SDO network with it,
// as BusLoop::pass does. No bus: frames go to a vector.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sdo_network.h"
#include "service_clock.h"
#include "transfer_summary.h"

namespace mb2co {
namespace master {
namespace {

TEST(ServiceClock, AFrameStampedBeforeTheLastPassGetsThePassTime) {
  ServiceClock clock;
  EXPECT_EQ(clock.at(1000), 1000u);  // a pass
  EXPECT_EQ(clock.at(996), 1000u);   // a frame stamped 4 µs before it
  EXPECT_EQ(clock.at(1003), 1003u);  // later times pass unchanged
  EXPECT_EQ(clock.at(1001), 1003u);
}

TEST(ServiceClock, TheWrapOfTheMicrosecondClockIsNoStepBack) {
  ServiceClock clock;
  EXPECT_EQ(clock.at(0xFFFFFFF0u), 0xFFFFFFF0u);
  EXPECT_EQ(clock.at(0x00000010u), 0x00000010u);  // 32 µs later, wrapped
  EXPECT_EQ(clock.at(0xFFFFFFF8u), 0x00000010u);  // before the wrap: earlier
}

bool record(void* ctx, const CanFrame& f) {
  static_cast<std::vector<CanFrame>*>(ctx)->push_back(f);
  return true;
}

TEST(TransferTime, AnAnswerStampedBeforeTheStartTakesNoTimeInsteadOf4294Seconds) {
  std::vector<CanFrame> sent;
  const CanSink sink = {&record, &sent};
  SdoNetwork net(1000000, 0);
  ServiceClock clock;
  Transfer t;
  t.node = 5;
  t.index = 0x1000;
  t.sub = 0;
  t.upload = true;
  net.queue(&t);
  // The pass at 1000 µs starts the upload (an even time: a start stamped
  // `now | 1` was 1 µs after the answer below even without the shift).
  net.process(clock.at(1000), sink);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].id, 0x605u);
  // The expedited answer, its receive time shifted 4 µs before the pass.
  CanFrame answer = {};
  answer.id = 0x585;
  answer.dlc = 8;
  const uint8_t bytes[8] = {0x43, 0x00, 0x10, 0x00, 0x91, 0x01, 0x03, 0x00};
  for (int i = 0; i < 8; ++i) answer.data[i] = bytes[i];
  net.on_frame(answer, clock.at(996), sink);
  ASSERT_TRUE(t.ok()) << t.failure();
  EXPECT_EQ(t.elapsed_us(), 0u);
  EXPECT_EQ(transfer_summary(t),
            "uploaded 4 bytes from node 5 1000h/0 in 0.000 s (0.0 KiB/s, expedited/segmented)");
  EXPECT_EQ(transfer_json(t, "f.bin"),
            "{\"node\":5,\"file\":\"f.bin\",\"bytes\":4,\"seconds\":0,\"block\":false,\"crc\":false}");
}

}  // namespace
}  // namespace master
}  // namespace mb2co
