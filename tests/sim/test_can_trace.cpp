// The simulated bus as a candump -L log (mb2co-lab --trace): the line format
// can-utils read, frames only, and a time line that only moves forward across
// the runs of one lab invocation.
#include <gtest/gtest.h>

#include "host/candump_text.h"
#include "sim/can_trace.h"
#include "sim/event_log.h"
#include "sim/scenarios.h"

namespace mb2co {
namespace sim {
namespace {

CanFrame frame(uint32_t id, uint8_t flags, uint8_t dlc, std::initializer_list<uint8_t> data) {
  CanFrame f{id, dlc, flags, {}};
  size_t i = 0;
  for (uint8_t b : data) f.data[i++] = b;
  return f;
}

TEST(CanTrace, LinesAreCandumpLogLines) {
  CanTrace t("can0");
  t.frame(1'500'000'123, frame(0x181, 0, 3, {0x01, 0x02, 0x00}));
  t.frame(2'000'000'000, frame(0x701, CanFrame::kRtr, 1, {}));
  t.frame(2'000'001'000, frame(0x1ABCDE, CanFrame::kExtended, 0, {}));
  EXPECT_EQ(t.text(),
            "(0000000001.500000) can0 181#010200\n"
            "(0000000002.000000) can0 701#R1\n"
            "(0000000002.000001) can0 001ABCDE#\n");
  EXPECT_EQ(t.frames(), 3u);
}

TEST(CanTrace, EachRunContinuesOneSecondAfterThePreviousRunsLastFrame) {
  CanTrace t;
  t.start_run();
  t.frame(5'000'000'000, frame(0x80, 0, 0, {}));
  t.start_run();  // the next run's clock starts at 0 again
  t.frame(0, frame(0x80, 0, 0, {}));
  EXPECT_EQ(t.text(), "(0000000005.000000) can0 080#\n(0000000006.000000) can0 080#\n");
}

TEST(CanTrace, ALabRunTracesEveryFrameOfItsBusAndNoErrorFrame) {
  EventLog log(true);
  CanTrace trace;
  log.set_can_trace(&trace);
  LineConfig c;
  c.stations = 3;
  const RunResult r = run_scenario(c, run_min_duration_s(c) * kNsPerS, &log, nullptr);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(trace.frames(), r.line.can_frames);
  EXPECT_GT(r.line.error_frames, 0u);  // the bring-up has them; they are not in the trace
  // The same frames as events.csv's "can" rows, in the same order.
  size_t rows = 0;
  for (size_t at = log.text().find(",can,"); at != std::string::npos; at = log.text().find(",can,", at + 1))
    ++rows;
  EXPECT_EQ(rows, trace.frames());
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
