// mb2co-master's unconfirmed services and its watch, on vcan0 against
// mb2co-node (the gateway firmware on Linux) with candump as the witness.
// ctest runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>
#include <signal.h>

#include <regex>

#include "master_cli.h"
#include "node_harness.h"
#include "wall_time.h"

namespace mb2co {
namespace test {
namespace {

/// The node under test: node id 3 of a 4-station ring, self-starting.
bool start_node(NodeProcess* node, TempDir* dir, int id = 3) {
  return node->start(
      {"--can", "vcan0", "--node-id", std::to_string(id), "--pty", dir->path("st" + std::to_string(id))});
}

/// Waits for the watch's next line containing `text`.
bool watch_says(LineChild& watch, const std::string& text, std::string* line = nullptr) {
  return watch.wait_line([&](const std::string& l) { return l.find(text) != std::string::npos; },
                         kVcanDeadline, line);
}

TEST(MasterNetwork, WatchFollowsNmtCommandsBootUpLossAndEmcy) {
  TempDir dir;
  LineChild watch;
  ASSERT_TRUE(start_master(&watch, {"watch", "--nodes", "3", "--heartbeat", "400"}));
  ASSERT_TRUE(watch_says(watch, "watching vcan0: 1 node ids, heartbeat consumer 400 ms"));

  NodeProcess node;
  ASSERT_TRUE(start_node(&node, &dir)) << node.error();
  EXPECT_TRUE(watch_says(watch, "node 3 boot-up"));
  // Self-starting (2000h/8 = 1): its heartbeats say operational; the watch
  // then reads its TPDO mappings and decodes TPDO1 (RUN state 2100h/2,
  // STOP2 counter 2100h/3).
  EXPECT_TRUE(watch_says(watch, "node 3 state boot-up -> operational"));
  EXPECT_TRUE(watch_says(watch, "node 3 TPDO1 2100h/2=0x0 2100h/3=0x0"));

  struct Step {
    const char* command;
    const char* target;
    const char* printed;
    const char* watch_sees;
  } const steps[] = {
      {"stop", "3", "nmt stop 3", "node 3 state operational -> stopped"},
      {"preop", "3", "nmt preop 3", "node 3 state stopped -> pre-operational"},
      {"start", "all", "nmt start all", "node 3 state pre-operational -> operational"},
      {"reset-comm", "3", "nmt reset-comm 3", "node 3 boot-up"},
  };
  for (const Step& s : steps) {
    const MasterRun run = run_master({"nmt", s.command, s.target});
    EXPECT_EQ(run.exit_code, 0) << s.command << ": " << run.err;
    EXPECT_EQ(run.text(), std::string(s.printed) + "\n");
    EXPECT_TRUE(watch_says(watch, s.watch_sees)) << "after nmt " << s.command;
  }
  // Monitoring starts again with the first heartbeat after the boot-up.
  EXPECT_TRUE(watch_says(watch, "node 3 state boot-up -> operational"));

  // TPDO1 remapped in pre-operational the CiA 301 way (invalid, count 0,
  // entries, count, valid): once operational again the watch reads the new
  // mapping and decodes by it.
  const std::vector<std::vector<std::string>> remap = {{"nmt", "preop", "3"},
                                                       {"write", "3", "1800", "1", "u32", "0x80000183"},
                                                       {"write", "3", "1A00", "0", "u8", "0"},
                                                       {"write", "3", "1A00", "1", "u32", "0x21000308"},
                                                       {"write", "3", "1A00", "0", "u8", "1"},
                                                       {"write", "3", "1800", "1", "u32", "0x183"},
                                                       {"nmt", "start", "3"}};
  for (const auto& args : remap) {
    const MasterRun run = run_master(args);
    EXPECT_EQ(run.exit_code, 0) << args[0] << " " << args.back() << ": " << run.err;
  }
  EXPECT_TRUE(watch_says(watch, "node 3 state pre-operational -> operational"));
  EXPECT_TRUE(watch_says(watch, "node 3 TPDO1 2100h/3=0x0"));

  // An RPDO shorter than its mapping (RPDO1 = TPDO1 of station 2, 3 bytes):
  // the node answers with EMCY 8210h, decoded by the watch.
  LineChild send;
  ASSERT_TRUE(send.start({"cansend", "vcan0", "182#01"}));
  ASSERT_EQ(send.wait_exit(kVcanDeadline), 0);
  std::string line;
  ASSERT_TRUE(watch_says(watch, "node 3 emcy 8210h", &line));
  EXPECT_NE(line.find("PDO length error"), std::string::npos) << line;
  EXPECT_NE(line.find("communication"), std::string::npos) << line;

  // Killed without a word: lost after the consumer time; back when it boots.
  ASSERT_TRUE(node.child.signal(SIGKILL));
  EXPECT_TRUE(watch_says(watch, "node 3 lost"));
  NodeProcess again;
  ASSERT_TRUE(start_node(&again, &dir)) << again.error();
  EXPECT_TRUE(watch_says(watch, "node 3 back"));

  ASSERT_TRUE(watch.signal(SIGINT));
  EXPECT_EQ(watch.wait_exit(kVcanDeadline), 0) << "watch ends cleanly on SIGINT";
}

TEST(MasterNetwork, GuardingWatchSeesTheNodeAnswerAndLosesItWhenKilled) {
  TempDir dir;
  NodeProcess node;
  ASSERT_TRUE(start_node(&node, &dir)) << node.error();
  // The node is switched from heartbeat to guarding (CiA 301: guarding only
  // with 1017h = 0): guard time 100 ms, life time factor 3.
  for (const auto& args : std::vector<std::vector<std::string>>{{"write", "3", "1017", "0", "u16", "0"},
                                                                {"write", "3", "100C", "0", "u16", "100"},
                                                                {"write", "3", "100D", "0", "u8", "3"}}) {
    const MasterRun run = run_master(args);
    ASSERT_EQ(run.exit_code, 0) << args[1] << ": " << run.err;
  }
  LineChild watch;
  ASSERT_TRUE(start_master(&watch, {"watch", "--nodes", "3", "--guard", "100", "--life", "3", "--raw"}));
  ASSERT_TRUE(watch_says(watch, "watching vcan0: 1 node ids, guarding every 100 ms, life time factor 3"));
  EXPECT_TRUE(watch_says(watch, "node 3 state unknown -> operational")) << "the first guarding answer";
  ASSERT_TRUE(node.child.signal(SIGKILL));
  EXPECT_TRUE(watch_says(watch, "node 3 lost"));
  ASSERT_TRUE(watch.signal(SIGINT));
  EXPECT_EQ(watch.wait_exit(kVcanDeadline), 0);
}

TEST(MasterNetwork, SyncSendsTheCounterOfItsOverflowAtItsPeriod) {
  LineChild candump;
  ASSERT_TRUE(start_candump(&candump));
  const MasterRun run = run_master({"sync", "--period", "20", "--count", "5", "--overflow", "3"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(run.out.size(), 5u) << run.text();
  EXPECT_EQ(run.out[0].rfind("sync 1 counter=1 at_ms=", 0), 0u) << run.out[0];
  EXPECT_EQ(run.out[4].rfind("sync 5 counter=2 at_ms=", 0), 0u) << run.out[4];

  std::vector<unsigned> counters;
  std::string line;
  while (counters.size() < 5 &&
         candump.wait_line([](const std::string&) { return true; }, kVcanDeadline, &line)) {
    unsigned id = 0;
    std::vector<unsigned> data;
    if (parse_candump(line, &id, &data) && id == 0x80) {
      ASSERT_EQ(data.size(), 1u) << line;
      counters.push_back(data[0]);
    }
  }
  EXPECT_EQ(counters, (std::vector<unsigned>{1, 2, 3, 1, 2})) << "1019h = 3: the counter runs 1..3";
  // Never early: the fifth SYNC is at least four periods after the first.
  double last_ms = 0;
  ASSERT_EQ(std::sscanf(run.out[4].c_str(), "sync 5 counter=2 at_ms=%lf", &last_ms), 1);
  EXPECT_GE(last_ms, 4 * 20.0 - 1.0);
}

TEST(MasterNetwork, TimeSendsTheHostClockAsTimeOfDayAtItsPeriod) {
  LineChild candump;
  ASSERT_TRUE(start_candump(&candump));
  const int64_t before_ms = master::wall_clock_unix_ms();
  const MasterRun run = run_master({"time", "--period", "50", "--count", "3"});
  const int64_t after_ms = master::wall_clock_unix_ms();
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(run.out.size(), 3u) << run.text();

  // What candump saw at 100h (1012h's default), decoded here by hand: 28
  // bits of ms after midnight little-endian, then 16 bits of days since 1984.
  std::vector<int64_t> sent_ms;
  std::string line;
  while (sent_ms.size() < 3 &&
         candump.wait_line([](const std::string&) { return true; }, kVcanDeadline, &line)) {
    unsigned id = 0;
    std::vector<unsigned> data;
    if (!parse_candump(line, &id, &data) || id != 0x100) continue;
    ASSERT_EQ(data.size(), 6u) << line;
    const int64_t ms = data[0] | data[1] << 8 | data[2] << 16 | (data[3] & 0x0F) << 24;
    const int64_t days = data[4] | data[5] << 8;
    const size_t n = sent_ms.size();
    // The master's line names the same instant.
    EXPECT_NE(run.out[n].find("days=" + std::to_string(days) + " ms=" + std::to_string(ms)),
              std::string::npos)
        << run.out[n] << " vs " << line;
    EXPECT_EQ(run.out[n].rfind("time " + std::to_string(n + 1) + " ", 0), 0u) << run.out[n];
    sent_ms.push_back(master::kCanopenEpochUnixMs + days * 86400000LL + ms);
  }
  ASSERT_EQ(sent_ms.size(), 3u);
  // The host's clock when each was sent, UTC: within the run, and whole
  // periods after the first, never early (a late frame does not move the
  // next one: 1 ms for the ms truncation; no upper bound under load).
  EXPECT_GE(sent_ms.front(), before_ms);
  EXPECT_LE(sent_ms.back(), after_ms);
  EXPECT_GE(sent_ms[1] - sent_ms[0], 50 - 1);
  EXPECT_GE(sent_ms[2] - sent_ms[0], 2 * 50 - 1);
  EXPECT_TRUE(std::regex_match(
      run.out[0], std::regex(R"(time 1 \d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z days=\d+ ms=\d+)")))
      << "UTC, ISO 8601: " << run.out[0];
}

TEST(MasterNetwork, BadCommandLinesAndAMissingInterfaceGiveOneLineAndTheirExitCode) {
  struct Case {
    std::vector<std::string> args;
    int code;
    const char* says;
  } const cases[] = {
      {{"nmt", "start", "128"}, 2, "nmt: node id must be 1..127 or all, got \"128\""},
      {{"nmt", "jump", "3"},
       2,
       "nmt: the NMT command must be start, stop, preop, reset or reset-comm, got \"jump\""},
      {{"nmt", "stop"},
       2,
       "missing operand: nmt start|stop|preop|reset|reset-comm NODE|all (try mb2co-master nmt --help)"},
      {{"sync", "--overflow", "1"}, 2, "--overflow 1 is not allowed"},
      {{"sync", "--count", "3"}, 2, "needs --period"},
      {{"time", "--count", "3"}, 2, "needs --period"},
      {{"time", "--cob-id", "800h"}, 2, "--cob-id"},
      {{"watch", "--nodes", "5-2"}, 2, "a node range must run upwards (5-7), got \"5-2\""},
      {{"fly"}, 2, "unknown command \"fly\""},
  };
  for (const Case& c : cases) {
    const MasterRun run = run_master(c.args);
    EXPECT_EQ(run.exit_code, c.code) << c.args[0];
    EXPECT_EQ(run.err.rfind("mb2co-master: ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(c.says), std::string::npos) << run.err;
    EXPECT_TRUE(run.out.empty());
  }
  LineChild child;
  ASSERT_TRUE(child.start({master_program(), "-i", "nosuch0", "nmt", "start", "all"}));
  child.close_stdin();
  EXPECT_EQ(child.wait_exit(kVcanDeadline), 3);
  const std::string err = child.stderr_text();
  EXPECT_NE(err.find("nosuch0"), std::string::npos) << err;
  EXPECT_EQ(err.find('\n'), err.size() - 1) << "one line: " << err;
}

}  // namespace
}  // namespace test
}  // namespace mb2co
