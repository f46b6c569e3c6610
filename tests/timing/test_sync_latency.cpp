// The week-13 SYNC bounds (seed 000 §5.2, §5.3) and §11's simpler
// alternative, against figures computed by hand from the frame lengths of
// seed 000 §2.10.
#include <gtest/gtest.h>

#include <cstring>

#include "timing/latency.h"
#include "timing/sync_latency.h"

namespace mb2co {
namespace timing {
namespace {

// 500 kbit/s (2 µs a bit), a uno-like firmware: a pass that handles a frame
// takes at least 674 µs, a frame waits at most 1,500 µs.
SyncParams lab_params() {
  SyncParams p;
  p.bitrate_bps = 500000;
  p.convention = WorstCase::kDavis;
  p.sync_period_us = 10000;
  p.sync_jitter_us = 1500;
  p.sync_queueing_worst_ns = 130000;
  p.transmission_type = 3;
  p.pdo_dlc = 1;
  p.pdo_queueing_worst_ns = 130000;
  p.pass_min_us = 674;
  p.fw_loop_us = 1500;
  p.debounce_us = 20000;
  return p;
}

const LatencyTerm* term(const LatencyBound& b, const char* name) {
  for (size_t i = 0; i < b.count; ++i) {
    if (std::strcmp(b.terms[i].name, name) == 0) return &b.terms[i];
  }
  return nullptr;
}

TEST(SyncBound, FrameTimesUntilReception) {
  const SyncParams p = lab_params();
  // SYNC, no data: 47 bits without stuffing, 3 of them IFS: 44 bits = 88 µs;
  // worst 47 + floor((34 - 1)/4) = 55 bits, 52 until EOF ends = 104 µs.
  EXPECT_EQ(sync_frame_best_ns(p), 88000u);
  EXPECT_EQ(sync_frame_worst_ns(p), 104000u);
  // One data byte: 55 bits - 3 = 104 µs; worst 55 + floor(41/4) = 65 - 3 = 124 µs.
  EXPECT_EQ(pdo_frame_best_ns(p), 104000u);
  EXPECT_EQ(pdo_frame_worst_ns(p), 124000u);
  // The seed's convention at 125 kbit/s (8 µs a bit): SYNC worst 47 +
  // floor(35/5) = 54 bits, 51 until EOF ends = 408 µs.
  SyncParams course = p;
  course.bitrate_bps = 125000;
  course.convention = WorstCase::kCourse;
  EXPECT_EQ(sync_frame_worst_ns(course), 408000u);
  EXPECT_EQ(sync_frame_best_ns(course), 352000u);
}

TEST(SyncBound, RoundTripIsSyncPlusProcessingPlusQueueingPlusPdo) {
  const LatencyBound b = sync_round_trip_bound(lab_params());
  ASSERT_EQ(b.count, 4u);
  EXPECT_STREQ(b.terms[0].name, "sync_frame");
  EXPECT_STREQ(b.terms[1].name, "sync_pass");
  EXPECT_STREQ(b.terms[2].name, "pdo_queueing");
  EXPECT_STREQ(b.terms[3].name, "pdo_frame");
  // best 88 + 674 + 0 + 104 µs; worst 104 + 1,500 + 130 + 124 µs.
  EXPECT_EQ(b.best_ns, 866000u);
  EXPECT_EQ(b.worst_ns, 1858000u);
  // The SYNC period and transmission type do not enter the round trip.
  SyncParams slow = lab_params();
  slow.sync_period_us = 100000;
  slow.transmission_type = 240;
  EXPECT_EQ(sync_round_trip_bound(slow).worst_ns, b.worst_ns);
}

TEST(SyncBound, RoundTripScalesWithTheBitRate) {
  SyncParams p = lab_params();
  p.pass_min_us = 0;
  p.fw_loop_us = 0;
  p.pdo_queueing_worst_ns = 0;
  p.bitrate_bps = 1000000;
  // Frames only: 44 + 52 bits best, 52 + 62 worst, at 1 µs a bit.
  EXPECT_EQ(sync_round_trip_bound(p).best_ns, 96000u);
  EXPECT_EQ(sync_round_trip_bound(p).worst_ns, 114000u);
  p.bitrate_bps = 125000;
  EXPECT_EQ(sync_round_trip_bound(p).best_ns, 768000u);
  EXPECT_EQ(sync_round_trip_bound(p).worst_ns, 912000u);
}

TEST(SyncBound, ResponseWaitsUpToNPeriodsPlusTheSyncSpread) {
  const LatencyBound b = sync_response_bound(lab_params());
  const LatencyTerm* wait = term(b, "sync_wait");
  ASSERT_NE(wait, nullptr);
  // 3 x 10 ms + jitter 1,500 + queueing 130 + stuffing spread (104 - 88) µs.
  EXPECT_EQ(wait->best_ns, 0u);
  EXPECT_EQ(wait->worst_ns, 31646000u);
  // best: debounce 20 ms + SYNC pass 674 + PDO 104 + RPDO pass 674 µs.
  EXPECT_EQ(b.best_ns, 21452000u);
  // worst: 20 ms + 1.5 + 31.646 + 1.5 + 0.13 + 0.124 + 1.5 ms.
  EXPECT_EQ(b.worst_ns, 56400000u);
  EXPECT_NE(term(b, "debounce"), nullptr);
  EXPECT_NE(term(b, "rpdo_pass"), nullptr);
}

TEST(SyncBound, EveryNthSyncAddsWholePeriods) {
  SyncParams p = lab_params();
  p.transmission_type = 1;
  const uint64_t one = sync_response_bound(p).worst_ns;
  p.transmission_type = 240;
  EXPECT_EQ(sync_response_bound(p).worst_ns - one, 239u * 10000000u);
  EXPECT_EQ(sync_response_bound(p).best_ns, 21452000u);  // the n-th SYNC may come at once
}

TEST(SyncBound, ParametersOutsideTheirRangeAreInvalid) {
  SyncParams p = lab_params();
  EXPECT_TRUE(sync_params_valid(p));
  p.transmission_type = 0;
  EXPECT_FALSE(sync_params_valid(p));
  p.transmission_type = 241;
  EXPECT_FALSE(sync_params_valid(p));
  p = lab_params();
  p.sync_period_us = 0;
  EXPECT_FALSE(sync_params_valid(p));
  p = lab_params();
  p.bitrate_bps = 2000000;
  EXPECT_FALSE(sync_params_valid(p));
}

TEST(SyncBound, WindowHoldsWhenTheRoundTripFitsIn) {
  SyncParams p = lab_params();
  EXPECT_TRUE(sync_window_met(p));  // no window
  p.sync_window_us = 1858;          // exactly the worst round trip
  EXPECT_TRUE(sync_window_met(p));
  p.sync_window_us = 1857;
  EXPECT_FALSE(sync_window_met(p));
}

// §11 simpler alternative: control on Arduino A, button and LED on B.
TEST(ArduinoControl, CanOnlyPathWithoutTheSerialRound) {
  LatencyParams p;
  p.debounce_us = 20000;
  p.fw_loop_us = 1000;
  p.inhibit_us = 10000;
  p.can_up_best_ns = 100000;
  p.can_up_worst_ns = 500000;
  p.can_down_best_ns = 100000;
  p.can_down_worst_ns = 600000;
  const LatencyBound b = arduino_control_latency(p);
  // best: debounce + both frames; worst: + input pass, 2 x (inhibit 10 ms +
  // a pass), both hops' R, control pass, LED pass.
  EXPECT_EQ(b.best_ns, 20200000u);
  EXPECT_EQ(b.worst_ns, 46100000u);
  EXPECT_NE(term(b, "control_pass"), nullptr);
  EXPECT_EQ(term(b, "poll_wait"), nullptr);
  // The PC-controlled path over the same hops adds the serial round.
  const LatencyBound pc = modbus_canopen_latency(p);
  EXPECT_GT(pc.worst_ns, b.worst_ns);
  EXPECT_GT(pc.best_ns, b.best_ns);
}

}  // namespace
}  // namespace timing
}  // namespace mb2co
