// Three mb2co-node processes in a ring on vcan0 (ctest runs this binary
// inside hil/uml/run-with-vcan.sh: the host's vcan or user-mode Linux).
// The test is the Modbus master (libmodbus) of each node on its own pty;
// candump (can-utils) records the bus for the whole run.
//
// Scenario (seed 000 §10, DESIGN §6): all three RUN; STOP2 pressed on node 1
// stops nodes 1 (cause 2) and 2 (cause 3, STOP2 of its previous station)
// while node 3 keeps running; node 2 killed: nodes 1 and 3 show it unknown
// within the heartbeat consumer time (1016h = 3 x 1017h = 300 ms); the bus
// carried exactly the COB-IDs of docs/mb2co-node.md.
#include <gtest/gtest.h>
#include <signal.h>
#include <time.h>

#include <cstdio>
#include <fstream>
#include <memory>
#include <set>

#include "node_harness.h"
#include "storage_damage.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kNodes = 3;
constexpr int32_t kConsumerUs = 300000;  // 3 x 100 ms heartbeat, derived by the nodes
// Slack allowed on top of the consumer time for the node to see its deadline
// pass. Its loop wakes at least every 1 ms; under user-mode Linux five
// processes share one virtual CPU and every syscall costs ~0.1 ms, and the
// host is shared: measured there, the reports came 299.9-301.8 ms after the
// last heartbeat (10 runs). The slack is one heartbeat period (100 ms), the
// bound that matters: a lost neighbour must show as unknown before a further
// heartbeat would have been due, and a stalled host must not fail the test.
constexpr int32_t kSlackUs = 100000;
// Both clocks are read from the same kernel; their offset is sampled once
// (by the test here, by the node for its receive stamps), and under
// user-mode Linux on a busy host the wall clock is slewed against the
// monotonic one between those samples: 2.5 ms seen in a CI run, 5.1 ms on a
// host at load 12 once the node slept until its deadline (ppoll) instead of
// waking every millisecond. The node's at_us is stamped at a loop pass,
// candump's at reception. 10 ms still tells a consumer time of 300 ms from
// one a pass or a unit off (290 ms).
constexpr int32_t kClockMapToleranceUs = 10000;
constexpr auto kUmlDeadline = 60s;  // bounds a failure only

// Input registers of docs/register-map.md.
constexpr int kIrRunState = 1, kIrStop2Count = 2, kIrStopCause = 3, kIrPrevRun = 6, kIrPrevStop2 = 7,
              kIrPrevStatus = 8, kIrNextRun = 9, kIrNextStatus = 10;

uint64_t clock_us(clockid_t id) {
  timespec ts{};
  clock_gettime(id, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

/// A candump -L line: "(seconds.micros) vcan0 ID#DATA".
struct LoggedFrame {
  uint64_t realtime_us;
  unsigned id;
  bool extended;
};

bool parse_candump(const std::string& line, LoggedFrame* f) {
  unsigned long sec = 0, usec = 0;
  char id[16] = {};
  if (std::sscanf(line.c_str(), "(%lu.%lu) %*s %15[0-9A-Fa-f]#", &sec, &usec, id) != 3) return false;
  f->realtime_us = static_cast<uint64_t>(sec) * 1000000u + usec;
  f->id = static_cast<unsigned>(std::stoul(id, nullptr, 16));
  f->extended = std::string(id).size() == 8;
  return true;
}

/// Modbus reads of one node until every (register, value) pair holds.
bool wait_inputs(ModbusMaster& m, const std::vector<std::pair<int, int>>& want) {
  return m.wait_inputs(want, kUmlDeadline);
}

/// The node's own time of the first state event after `after_us` whose
/// `field` (prev/next) begins with `prefix`; -1 when none came.
int64_t event_time(NodeProcess& node, const char* field, const std::string& prefix, uint32_t after_us) {
  std::string line;
  const bool seen = node.wait_event(
      "state ",
      [&](const std::string& l) {
        return static_cast<int32_t>(at_us_of(l) - after_us) >= 0 && field_of(l, field).rfind(prefix, 0) == 0;
      },
      kUmlDeadline, &line);
  return seen ? static_cast<int64_t>(at_us_of(line)) : -1;
}

TEST(Ring, Stop2StopsTwoStationsAndALostNodeShowsUnknown) {
  TempDir dir;
  // candump first, and known to listen before any node starts.
  LineChild candump;
  const Status listening = start_candump_listening(candump, kUmlDeadline);
  ASSERT_TRUE(listening) << listening.message();

  NodeProcess node[kNodes];
  ModbusMaster master[kNodes];
  for (int i = 0; i < kNodes; ++i) {
    const std::string id = std::to_string(i + 1);
    ASSERT_TRUE(node[i].start({"--can", "vcan0", "--node-id", id, "--stations", "3", "--topology", "ring",
                               "--pty", dir.path(id + ".pty")},
                              kUmlDeadline))
        << node[i].error();
    ASSERT_TRUE(master[i].open(node[i].device(), 2s)) << master[i].error();
  }
  for (int i = 0; i < kNodes; ++i)
    ASSERT_EQ(modbus_write_register(master[i].ctx(), 0, 1), 1) << "RUN command";
  // All running, each hearing both neighbours (heartbeat and a TPDO1 that
  // says RUN): node 2 then has a baseline of node 1's STOP2 counter.
  for (int i = 0; i < kNodes; ++i) {
    ASSERT_TRUE(wait_inputs(
        master[i],
        {{kIrRunState, 1}, {kIrPrevStatus, 1}, {kIrPrevRun, 1}, {kIrNextStatus, 1}, {kIrNextRun, 1}}))
        << "node " << i + 1 << " not running with both neighbours";
  }

  ASSERT_EQ(node[0].ask("click STOP2 100", "ok"), "ok");
  EXPECT_TRUE(wait_inputs(master[0], {{kIrRunState, 0}, {kIrStopCause, 2}, {kIrStop2Count, 1}}))
      << "node 1 stopped by its own STOP2";
  EXPECT_TRUE(wait_inputs(master[1], {{kIrRunState, 0}, {kIrStopCause, 3}, {kIrPrevStop2, 1}}))
      << "node 2 stopped by the STOP2 of node 1";
  // Node 3 has heard node 2's new state (so it would have reacted by now),
  // and runs on.
  EXPECT_TRUE(wait_inputs(master[2], {{kIrPrevRun, 0}}));
  EXPECT_EQ(master[2].input_register(kIrRunState), 1) << "node 3 keeps running";
  EXPECT_EQ(master[2].input_register(kIrStopCause), 0);

  // Node 2 dies without a word. Clock offset for candump's (realtime) stamps.
  const int64_t realtime_minus_mono_us =
      static_cast<int64_t>(clock_us(CLOCK_REALTIME)) - static_cast<int64_t>(clock_us(CLOCK_MONOTONIC));
  const uint32_t killed_at = monotonic_us();
  ASSERT_TRUE(node[1].child.signal(SIGKILL));
  EXPECT_EQ(node[1].child.wait_exit(kUmlDeadline), 128 + SIGKILL);
  const int64_t lost_at_1 = event_time(node[0], "next", "2:0:", killed_at);
  const int64_t lost_at_3 = event_time(node[2], "prev", "2:0:", killed_at);
  ASSERT_GE(lost_at_1, 0) << "node 1 never showed node 2 unknown";
  ASSERT_GE(lost_at_3, 0) << "node 3 never showed node 2 unknown";
  EXPECT_TRUE(wait_inputs(master[0], {{kIrNextStatus, 0}})) << "and says so over Modbus";
  EXPECT_TRUE(wait_inputs(master[2], {{kIrPrevStatus, 0}}));

  for (int i : {0, 2}) {
    master[i].close();
    EXPECT_EQ(node[i].stop(), 0) << "node " << i + 1;
  }
  ASSERT_TRUE(candump.signal(SIGINT));
  std::vector<LoggedFrame> frames;
  std::string line;
  while (candump.wait_line([](const std::string&) { return true; }, kUmlDeadline, &line)) {
    LoggedFrame f{};
    if (parse_candump(line, &f)) frames.push_back(f);
  }
  EXPECT_EQ(candump.wait_exit(kUmlDeadline), 0);

  // Exactly the documented COB-IDs: boot-up/heartbeat 700h+id, TPDO1 (line
  // state) 180h+id, TPDO2 (buttons) 280h+id of every node, and EMCY 80h+id
  // of the two nodes that lost a heartbeat.
  std::set<unsigned> seen;
  uint64_t last_heartbeat_2 = 0;
  for (const LoggedFrame& f : frames) {
    EXPECT_FALSE(f.extended) << "a node sent an extended frame";
    if (f.extended) continue;
    seen.insert(f.id);
    if (f.id == 0x702) last_heartbeat_2 = f.realtime_us;
  }
  const std::set<unsigned> documented{0x701, 0x702, 0x703, 0x181, 0x182, 0x183,
                                      0x281, 0x282, 0x283, 0x081, 0x083};
  EXPECT_EQ(seen, documented);

  // When: from the last heartbeat of node 2 on the bus to each node's own
  // report, the consumer time and not less; from the kill, at most that.
  ASSERT_NE(last_heartbeat_2, 0u);
  const uint32_t last_hb_mono =
      static_cast<uint32_t>(static_cast<int64_t>(last_heartbeat_2) - realtime_minus_mono_us);
  for (const int64_t lost_at : {lost_at_1, lost_at_3}) {
    const int32_t after_hb = static_cast<int32_t>(static_cast<uint32_t>(lost_at) - last_hb_mono);
    const int32_t after_kill = static_cast<int32_t>(static_cast<uint32_t>(lost_at) - killed_at);
    std::printf("heartbeat loss reported %.1f ms after the last heartbeat, %.1f ms after the kill\n",
                after_hb / 1000.0, after_kill / 1000.0);
    RecordProperty("after_last_heartbeat_us", after_hb);
    EXPECT_GE(after_hb, kConsumerUs - kClockMapToleranceUs) << "declared lost before the consumer time";
    EXPECT_LE(after_hb, kConsumerUs + kSlackUs);
    EXPECT_LE(after_kill, kConsumerUs + kSlackUs);
  }
}

// Issue 16 item 6 on the bus: a node whose saved parameters are damaged
// sends its boot-up, then EMCY 5530h with error register bit 0 (generic).
TEST(Ring, DamagedSavedParametersSendEmcy5530AfterTheBootUp) {
  TempDir dir;
  std::vector<uint8_t> image;
  for (const storage_damage::Kind& kind : storage_damage::kinds()) {
    if (std::string(kind.name) == "random bytes") {
      ASSERT_TRUE(kind.apply(image));
    }
  }
  ASSERT_EQ(image.size(), 1024u);
  {
    std::ofstream f(dir.path("eeprom"), std::ios::binary);
    f.write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
  }
  LineChild candump;
  const Status listening = start_candump_listening(candump, kUmlDeadline);
  ASSERT_TRUE(listening) << listening.message();
  NodeProcess node;
  ASSERT_TRUE(node.start(
      {"--can", "vcan0", "--node-id", "5", "--pty", dir.path("5.pty"), "--eeprom", dir.path("eeprom")},
      kUmlDeadline))
      << node.error();
  EXPECT_TRUE(candump.wait_line([](const std::string& l) { return l.find(" 705#00") != std::string::npos; },
                                kUmlDeadline))
      << "boot-up of node 5 (the defaults: the damaged id is not used)";
  EXPECT_TRUE(candump.wait_line(
      [](const std::string& l) { return l.find(" 085#305501") != std::string::npos; }, kUmlDeadline))
      << "EMCY 5530h, error register 01h, after the boot-up";
  EXPECT_EQ(node.stop(), 0);
  EXPECT_NE(node.child.stderr_text().find("damaged"), std::string::npos);
  ASSERT_TRUE(candump.signal(SIGINT));
  EXPECT_EQ(candump.wait_exit(kUmlDeadline), 0);
}

// Inside the same sandbox, where CAN exists: a missing interface is a
// one-line error and exit code 1.
TEST(Ring, MissingInterfaceExits1WithOneLine) {
  LineChild child;
  ASSERT_TRUE(child.start({node_program(), "--can", "nosuch0"}));
  EXPECT_EQ(child.wait_exit(kUmlDeadline), 1);
  EXPECT_EQ(child.stderr_text(), "mb2co-node: socketcan nosuch0: no such interface\n");
}

}  // namespace
}  // namespace test
}  // namespace mb2co
