// Issue 25 item 4: a quiet line must not lose frames in the MCP2515. The
// real station image (node 1, defaults: a ring of 4, so it consumes node 2's
// TPDO1 182h and heartbeat 702h) in simavr, in process (UnoRig), with node 2
// as a producer with the station's defaults: TPDO1 event timer and heartbeat
// both 100 ms, so the two frames leave node 2 in one pass and reach the bus
// back to back (or a little apart). Every phase of the pair against the
// image's own passes is tried: the pair drifts 13 µs a period against the
// image's 100 ms timers, and the gap between the two frames varies from
// none to 0.3 ms.
//
// Before the fix both ids were in RXB1 (the filter planner's layout): the
// second frame found RXB1 still full whenever it came during a pass that
// had not yet read the first, and the image reported EMCY 8110h (and, once
// heartbeats were lost, 8130h).
#include <gtest/gtest.h>

#include <memory>

#include "rig_frame.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {
namespace {

constexpr uint64_t kPeriodUs = 100000 + 13;  ///< node 2's 1017h and 1800h/5, drifting against node 1's
constexpr int kPairs = 200;                  ///< 20 simulated seconds
constexpr uint64_t kMaxGapUs = 300;

bool is_emcy(const CanFrame& f, uint16_t code) {
  return f.id == 0x081 && f.dlc == 8 && f.data[0] == (code & 0xFF) && f.data[1] == (code >> 8);
}

TEST(UnoQuietLine, NoReceiveOverflowWhenNode2sTpdo1AndHeartbeatComeTogether) {
  auto rig = std::make_unique<UnoRig>(gateway_image());  // large: not on the stack
  const Status loaded = rig->load(MB2CO_UNO_GATEWAY_ELF);
  ASSERT_TRUE(loaded) << loaded.message();
  // Boot, and the filter plan for the ids of node 1 in a ring of 4 (tens of
  // ms of planner steps) programmed before node 2 starts.
  ASSERT_TRUE(rig->run_until_us(500000));
  ASSERT_EQ(rig->booted_node(), 1);
  rig->take_can_out();

  int emcy_8110 = 0;
  int emcy_8130 = 0;
  uint64_t t_us = rig->now_us();
  for (int k = 0; k < kPairs; ++k) {
    t_us += kPeriodUs;
    const uint64_t gap_us = static_cast<uint64_t>(k) * 37u % kMaxGapUs;
    rig->can_in(rig_frame(0x182, {0x01, static_cast<uint8_t>(k), 0x00}), t_us);  // RUN, STOP2 count
    rig->can_in(rig_frame(0x702, {0x05}), t_us + gap_us);                        // operational
    ASSERT_TRUE(rig->run_until_us(t_us + kPeriodUs / 2));
    for (const CanWire::Sent& s : rig->take_can_out()) {
      emcy_8110 += is_emcy(s.frame, 0x8110);
      emcy_8130 += is_emcy(s.frame, 0x8130);
    }
  }
  EXPECT_EQ(rig->wire().rx_overflowed(), 0u) << "frames lost in the MCP2515's full receive buffers";
  EXPECT_EQ(emcy_8110, 0) << "EMCY 8110h (CAN overrun)";
  EXPECT_EQ(emcy_8130, 0) << "EMCY 8130h (heartbeat of node 2 lost)";
  RecordProperty("rx_overflowed", static_cast<int>(rig->wire().rx_overflowed()));
}

}  // namespace
}  // namespace uno
}  // namespace mb2co
