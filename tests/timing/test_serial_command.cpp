// `mb2co-timing serial` (pcapp/timing/serial_command.cpp) driven through
// run(): the figures of shared/timing's serial segment, computed by hand
// here, and one-line refusals of what cannot work.
#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "commands.h"

namespace mb2co {
namespace timing_cli {
namespace {

struct Outcome {
  int status;
  std::string out, err;
};

Outcome serial(std::vector<std::string> args) {
  args.insert(args.begin(), {"mb2co-timing", "serial"});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(&a[0]);
  std::ostringstream out, err;
  const int status = run(static_cast<int>(argv.size()), argv.data(), out, err);
  return Outcome{status, out.str(), err.str()};
}

TEST(SerialCommand, FifteenNodesOnASevenBitSegment) {
  const Outcome o = serial({"--csv"});
  ASSERT_EQ(o.status, 0) << o.err;
  // 115200 baud: 87 µs a byte; SYNC 11 bytes worst = 957 µs; an 8-byte
  // message 25 bytes worst = 2175 µs. Polling: 15 (3600 + 957) = 68,355,
  // latency + 2175. Token: 15 x 3600 = 54,000, idle 15 x 957, T_recover
  // 3600 + 100 + 957.
  EXPECT_EQ(o.out,
            "nodes,access,cycle_us,idle_us,latency_us,recover_us\n"
            "15,polling,68355,68355,70530,\n"
            "15,token,54000,14355,56175,4657\n");
}

TEST(SerialCommand, NodeListsEightBitsAndTheBridge) {
  const Outcome o = serial(
      {"--nodes", "4,31", "--id-bits", "8", "--access=token", "--bridge-us", "200", "--dlc", "2", "--json"});
  ASSERT_EQ(o.status, 0) << o.err;
  // 2 data bytes: 13 bytes worst = 1131 µs; 4 nodes: round 14,400 µs. To
  // CAN adds 200 µs and the DLC-2 frame, 55 + 20 = 75 bits at 500 kbit/s =
  // 150 µs; from CAN: 200 µs, then a round and the message.
  EXPECT_NE(o.out.find("\"message_worst_us\": 1131"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find(
                "{\"nodes\": 4, \"access\": \"token\", \"cycle_us\": 14400, \"idle_us\": 3828, "
                "\"latency_us\": 15531, \"recover_us\": 4657, \"to_can_us\": 15881, \"from_can_us\": 15731}"),
            std::string::npos)
      << o.out;
  EXPECT_NE(o.out.find("{\"nodes\": 31, \"access\": \"token\", \"cycle_us\": 111600, \"idle_us\": 29667, "
                       "\"latency_us\": 112731"),
            std::string::npos)
      << o.out;
}

TEST(SerialCommand, WhatDoesNotFitAWindowHasNoBound) {
  const Outcome o = serial({"--access", "polling", "--ahead", "8,8", "--csv"});
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_EQ(o.out, "nodes,access,cycle_us,idle_us,latency_us,recover_us\n15,polling,68355,68355,,\n");
}

TEST(SerialCommand, RefusalsInOneLineAsUsageErrors) {
  Outcome o = serial({"--nodes", "31"});
  EXPECT_EQ(o.status, 2);
  EXPECT_EQ(o.err,
            "mb2co-timing: --nodes must be a list of whole numbers 1..15, got \"31\" "
            "(the 7-bit set has node ids 1..15)\n");
  o = serial({"--window-us", "1000", "--access", "token"});
  EXPECT_EQ(o.status, 2);
  // Guard 100 + T_sync 957 + the longest message (27 bytes) 2349 µs.
  EXPECT_EQ(o.err,
            "mb2co-timing: --window-us 1000 holds no longest message and the pass: at least 3406 us\n");
  EXPECT_EQ(serial({"--nodes", "4,,15"}).status, 2);
  EXPECT_EQ(serial({"--ahead", "9"}).status, 2);
  // The program's parser checks the table's kinds before the command runs.
  EXPECT_EQ(serial({"--id-bits", "9"}).err, "mb2co-timing: --id-bits must be 11|8|7|6, got \"9\"\n");
  EXPECT_EQ(serial({"--access", "ring"}).status, 2);
  EXPECT_EQ(serial({"--json", "--csv"}).err, "mb2co-timing: choose one of --json and --csv\n");
  o = serial({"--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.out.find("--access polling|token|both"), std::string::npos);
}

}  // namespace
}  // namespace timing_cli
}  // namespace mb2co
