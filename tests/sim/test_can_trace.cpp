// The simulated bus as a candump -L log (mb2co-lab --trace): the line format
// can-utils read, frames only, and a time line that only moves forward across
// the runs of one lab invocation.
#include <gtest/gtest.h>

#include "host/candump_text.h"
#include "host/pcap_can.h"
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

// A candump -L log read back (host/candump_text.h) and turned into pcap of
// LINKTYPE_CAN_SOCKETCAN (host/pcap_can.h), as mb2co-lab --trace FILE.pcap
// and mb2co-node --trace-can FILE.pcap write it: every frame kind survives
// the round trip, the record is the SocketCAN layout, and what is not a
// frame line is refused by its line number.
TEST(CandumpLog, EveryFrameKindReadsBackAsWritten) {
  const CanFrame frames[] = {frame(0x181, 0, 3, {0x01, 0x02, 0x00}),
                             frame(0x000, 0, 2, {0x01, 0x05}),
                             frame(0x701, CanFrame::kRtr, 1, {}),
                             frame(0x7FF, CanFrame::kRtr, 0, {}),
                             frame(0x1ABCDE, CanFrame::kExtended, 8, {1, 2, 3, 4, 5, 6, 7, 8}),
                             frame(0x80, 0, 0, {})};
  for (const CanFrame& f : frames) {
    const std::string line = candump_log_line(1732561234567890ull, "vcan0", f);
    uint64_t t_us = 0;
    std::string iface;
    CanFrame back = {};
    ASSERT_TRUE(parse_candump_log_line(line.substr(0, line.size() - 1), &t_us, &iface, &back)) << line;
    EXPECT_EQ(t_us, 1732561234567890ull);
    EXPECT_EQ(iface, "vcan0");
    EXPECT_EQ(candump_frame_text(back), candump_frame_text(f)) << line;
    EXPECT_EQ(back.flags, f.flags) << line;
  }
}

TEST(CandumpLog, WhatIsNotAFrameLineIsRefused) {
  uint64_t t_us = 0;
  std::string iface;
  CanFrame f = {};
  for (const char* bad :
       {"", "(1.000000) can0", "(1.000000) can0 1234#00", "(1.0000) can0 123#00", "(1.000000) can0 123#0",
        "(1.000000) can0 123#001122334455667788", "1.000000 can0 123#", "(1.000000) can0 800#",
        "(1.000000) can0 123##0011", "(x.000000) can0 123#"}) {
    EXPECT_FALSE(parse_candump_log_line(bad, &t_us, &iface, &f)) << bad;
  }
  std::string pcap;
  const Status s = pcap_from_candump_log("(1.000000) can0 123#00\n\nnonsense\n", &pcap);
  EXPECT_EQ(s.message(), "candump log line 3 is not a frame: nonsense");
}

std::string bytes(std::initializer_list<int> b) {
  std::string s;
  for (int v : b) s += static_cast<char>(v);
  return s;
}

TEST(Pcap, HeaderAndRecordsAreTheSocketCanLayout) {
  EXPECT_EQ(pcap_can_file_header(), bytes({0xD4, 0xC3, 0xB2, 0xA1, 2,    0,    4, 0, 0,   0, 0, 0,
                                           0,    0,    0,    0,    0xFF, 0xFF, 0, 0, 227, 0, 0, 0}));
  // 2.000003 s, extended id 1ABCDEh with 2 bytes; then a standard RTR with dlc 4.
  std::string pcap;
  ASSERT_TRUE(
      pcap_from_candump_log("(0000000002.000003) can0 001ABCDE#BEEF\n(2.000004) can0 701#R4\n", &pcap));
  ASSERT_EQ(pcap.size(), kPcapFileHeaderBytes + 2 * kPcapCanRecordBytes);
  EXPECT_EQ(pcap.substr(24, 32),
            bytes({2,    0,    0,    0,    3, 0, 0, 0, 16,   0,    0, 0, 16, 0, 0, 0,  // record
                   0x80, 0x1A, 0xBC, 0xDE, 2, 0, 0, 0, 0xBE, 0xEF, 0, 0, 0,  0, 0, 0}));
  EXPECT_EQ(pcap.substr(56 + 16), bytes({0x40, 0, 0x07, 0x01, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}));
}

TEST(Pcap, OnlyPathsEndingInPcapArePcap) {
  EXPECT_TRUE(is_pcap_path("out/trace.pcap"));
  EXPECT_FALSE(is_pcap_path("trace.log"));
  EXPECT_FALSE(is_pcap_path("trace.pcapng"));
  EXPECT_FALSE(is_pcap_path(".pcap"));
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
