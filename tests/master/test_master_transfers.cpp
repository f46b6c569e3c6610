// mb2co-master's SDO transfers on vcan0 against the real Uno image
// (mb2co-uno, node 1) and mb2co-node (nodes 2..4): scan, typed read/write
// (on the command line and via the EDS), every transfer type, the abort
// codes of refusals and of silence, and the watchdog: a node killed in the
// middle of a segmented transfer ends that transfer within the heartbeat
// consumer time while the transfers to the others finish.
// ctest runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include "master_cli.h"
#include "node_harness.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

void write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// mb2co-node's 1F50h/1 at start: 131,072 bytes, byte i = i mod 251.
std::vector<uint8_t> program_data_pattern() {
  std::vector<uint8_t> v(131072);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<uint8_t>(i % 251);
  return v;
}

bool start_node(NodeProcess* node, TempDir* dir, int id) {
  return node->start(
      {"--can", "vcan0", "--node-id", std::to_string(id), "--pty", dir->path("st" + std::to_string(id))});
}

class MasterTransfers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    uno_ = new UnoProcess;
    ASSERT_TRUE(uno_->start({"--can", "vcan0", "--pty", dir_->path("uno.pty")}, kVcanDeadline))
        << uno_->error();
    for (int id = 2; id <= 3; ++id) {
      nodes_[id] = new NodeProcess;
      ASSERT_TRUE(start_node(nodes_[id], dir_, id)) << nodes_[id]->error();
    }
  }
  static void TearDownTestSuite() {
    for (NodeProcess*& n : nodes_) {
      delete n;
      n = nullptr;
    }
    delete uno_;
    delete dir_;
  }
  static TempDir* dir_;
  static UnoProcess* uno_;
  static NodeProcess* nodes_[4];
};
TempDir* MasterTransfers::dir_ = nullptr;
UnoProcess* MasterTransfers::uno_ = nullptr;
NodeProcess* MasterTransfers::nodes_[4] = {};

TEST_F(MasterTransfers, ScanFindsTheUnoAndTheNodesWithTheirIdentity) {
  const MasterRun run = run_master({"-t", "300", "scan", "1", "10"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  ASSERT_EQ(run.out.size(), 4u) << run.text() << uno_->ask("bus?", "bus ");
  for (int id = 1; id <= 3; ++id) {
    const std::string& l = run.out[static_cast<size_t>(id - 1)];
    EXPECT_EQ(l.rfind("node " + std::to_string(id) +
                          ": device type 0x00030191, vendor 0x00000000, product 0x00000B2C",
                      0),
              0u)
        << l;
    EXPECT_NE(l.find("name \"mb2co gateway\""), std::string::npos) << l;
  }
  EXPECT_EQ(run.out[3], "scan: 3 of 10 node ids answered");
}

TEST_F(MasterTransfers, TypedReadAndWriteOnTheCommandLineAndViaTheEds) {
  MasterRun run = run_master({"read", "1-3", "1008", "0", "vs"});
  // On failure: the Uno's chip counters (overflowed=) and how far its
  // image's clock (sim_us) lags the wall (at_us).
  ASSERT_EQ(run.exit_code, 0) << run.err << uno_->ask("bus?", "bus ") << "\n"
                              << uno_->ask("stack?", "stack ");
  EXPECT_EQ(run.text(), "node 1: mb2co gateway\nnode 2: mb2co gateway\nnode 3: mb2co gateway\n");
  // The Uno's debounce time 2000h/6 (ms): written, read back with the type
  // the EDS gives, then restored.
  run = run_master({"--eds", MB2CO_GATEWAY_EDS, "read", "1", "2000h", "6"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string before = run.text();
  run = run_master({"--eds", MB2CO_GATEWAY_EDS, "write", "1", "0x2000", "6", "35"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.text(), "node 1 2000h/6: 2 bytes written\n");
  run = run_master({"read", "1", "2000", "6", "u16"});
  EXPECT_EQ(run.text(), "0x23\n");
  run = run_master({"--json", "read", "1", "2000", "6", "u16"});
  EXPECT_EQ(run.text(), "{\"node\":1,\"index\":\"2000\",\"sub\":6,\"value\":\"0x23\",\"bytes\":2}\n");
  run = run_master(
      {"--eds", MB2CO_GATEWAY_EDS, "write", "1", "2000", "6", before.substr(0, before.size() - 1)});
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

TEST_F(MasterTransfers, RefusalsAndSilenceGiveTheAbortCodeAndTheirExitCode) {
  struct Case {
    std::vector<std::string> args;
    int code;
    const char* says;
  } const cases[] = {
      {{"read", "2", "5FFF", "0", "u8"}, 1, "node 2 5FFFh/0: SDO abort 06020000h (object does not exist"},
      {{"read", "1", "1018", "9", "u32"},
       1,
       "node 1 1018h/9: SDO abort 06090011h (sub-index does not exist)"},
      {{"write", "3", "1008", "0", "vs", "renamed"}, 1, "06010002h (attempt to write a read only object)"},
      {{"write", "2", "2000", "6", "u8", "1"}, 1, "06070013h"},
      {{"read", "2", "2000", "6", "u8"}, 1, "node 2 2000h/6: 2 bytes, not a UNSIGNED8 (1 bytes)"},
      {{"upload", "2", "1008", "0", "/nonexistent/dir/file"},
       2,
       "upload: cannot write /nonexistent/dir/file.part"},
      // Block transfer is not in the Uno image (its EDS says so): refused.
      {{"upload", "1", "1008", "0", "/dev/null", "--block"}, 1, "05040001h"},
      {{"-t", "200", "read", "9", "1000", "0", "u32"},
       4,
       "node 9 1000h/0: SDO abort sent 05040000h (SDO protocol timed out)"},
      {{"read", "2", "1000", "0", "q7"},
       2,
       "read: TYPE must be one of b u8 u16 u24 u32 u64 i8 i16 i32 i64 r32 r64 vs os us d, got \"q7\""},
      {{"write", "2", "2000", "6", "u16", "70000"}, 2, "out of range"},
      {{"read", "2", "1G00", "0", "u8"}, 2, "read: index must be hexadecimal 0000..FFFF, got \"1G00\""},
  };
  for (const Case& c : cases) {
    const MasterRun run = run_master(c.args);
    EXPECT_EQ(run.exit_code, c.code) << run.err;
    EXPECT_NE(run.err.find(c.says), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << "one line: " << run.err;
  }
}

TEST_F(MasterTransfers, EveryTransferTypeMovesTheBytesExactly) {
  const std::string up = dir_->path("up.bin");
  // Segmented upload of a string, expedited of a number.
  MasterRun run = run_master({"upload", "2", "1008", "0", up, "--segmented"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::vector<uint8_t> name = file_bytes(up);
  EXPECT_EQ(std::string(name.begin(), name.end()), "mb2co gateway");
  // 1F50h/1 as the node starts: 128 KiB, block (with CRC) and segmented.
  const std::vector<uint8_t> pattern = program_data_pattern();
  run = run_master({"upload", "2", "1F50", "1", up, "--block"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.text().find("uploaded 131072 bytes from node 2 1F50h/1"), std::string::npos) << run.text();
  EXPECT_NE(run.text().find("block with CRC"), std::string::npos) << run.text();
  EXPECT_TRUE(file_bytes(up) == pattern) << "block upload differs from the node's content";
  run = run_master({"upload", "3", "1F50", "1", up, "--segmented"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(file_bytes(up) == pattern) << "segmented upload differs from the node's content";

  // 70,001 bytes of other content: block download to node 2, segmented to
  // node 3, each read back by the other transfer type.
  std::vector<uint8_t> content(70001);
  for (size_t i = 0; i < content.size(); ++i) content[i] = static_cast<uint8_t>((i * 7 + (i >> 9)) & 0xFF);
  const std::string src = dir_->path("src.bin");
  write_file(src, content);
  run = run_master({"download", "2", "1F50", "1", src, "--block"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  run = run_master({"download", "3", "1F50", "1", src, "--segmented"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  run = run_master({"upload", "2", "1F50", "1", up, "--segmented"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(file_bytes(up) == content);
  run = run_master({"upload", "3", "1F50", "1", up, "--block"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(file_bytes(up) == content);
  // A download too large for the object is refused whole: the content stays.
  write_file(src, std::vector<uint8_t>(1048577, 0x55));
  run = run_master({"download", "2", "1F50", "1", src, "--block"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("06070012h"), std::string::npos) << run.err;
  run = run_master({"upload", "2", "1F50", "1", up, "--block"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(file_bytes(up) == content) << "a refused download changed the object";
}

/// "(seconds.micros) vcan0 ..." → µs of the candump clock.
uint64_t candump_us(const std::string& line) {
  unsigned long sec = 0, usec = 0;
  return std::sscanf(line.c_str(), "(%lu.%lu)", &sec, &usec) == 2
             ? static_cast<uint64_t>(sec) * 1000000u + usec
             : 0;
}

TEST(MasterWatchdog, ANodeKilledMidTransferAbortsWithinTheConsumerTimeTheOthersFinish) {
  TempDir dir;
  LineChild candump;
  ASSERT_TRUE(start_candump(&candump));
  NodeProcess nodes[3];
  for (int k = 0; k < 3; ++k) ASSERT_TRUE(start_node(&nodes[k], &dir, 4 + k)) << nodes[k].error();
  // Segmented uploads of 128 KiB from nodes 4, 5, 6 at once; SDO timeout 10 s,
  // watchdog (heartbeat consumer time) 1000 ms (the nodes beat every 100 ms: ten beats
  // missed, so a node stalled by a busy host under user-mode Linux is not
  // taken for dead).
  LineChild master;
  ASSERT_TRUE(start_master(&master, {"-t", "10000", "--watchdog", "1000", "upload", "4-6", "1F50", "1",
                                     dir.path("up"), "--segmented"}));
  master.close_stdin();
  // Node 5 dies once its transfer is well under way: its 200th segment.
  // Its heartbeats (705#05) are followed from the start: the consumer time
  // runs from the last one, which may come before the 200th segment (a node
  // that sleeps until its next deadline sends 200 segments within one
  // heartbeat period).
  int segments = 0;
  uint64_t last_heartbeat_us = 0;
  std::string line;
  ASSERT_TRUE(candump.wait_line(
      [&](const std::string& l) {
        if (l.find(" 705#") != std::string::npos) last_heartbeat_us = candump_us(l);
        return l.find(" 585#") != std::string::npos && ++segments == 200;
      },
      kVcanDeadline, &line));
  ASSERT_TRUE(nodes[1].child.signal(SIGKILL));
  // The master's abort to node 5: 605# 80 50 1F 01 00 00 04 05 (05040000h),
  // timed from node 5's last heartbeat, where the consumer time starts.
  std::string tail;  // node 5's last frames, for a failure message
  ASSERT_TRUE(candump.wait_line(
      [&](const std::string& l) {
        if (l.find(" 705#") != std::string::npos) last_heartbeat_us = candump_us(l);
        if (l.find(" 585#") != std::string::npos || l.find(" 705#") != std::string::npos ||
            l.find("DROPCOUNT") != std::string::npos)
          tail = l;
        return l.find(" 605#80501F0100000405") != std::string::npos;
      },
      kVcanDeadline, &line))
      << "no abort to node 5; its last frame: " << tail << "\n"
      << master.stderr_text();
  ASSERT_NE(last_heartbeat_us, 0u);
  const double abort_after_ms = static_cast<double>(candump_us(line) - last_heartbeat_us) / 1000.0;
  // Not before the consumer time, less the clock-mapping tolerance: the
  // master times the heartbeat by its own receive stamp (the kernel's wall
  // clock mapped onto its monotonic clock, sampled once), candump by the
  // wall clock; under user-mode Linux the two differ by up to a few ms
  // (node.ring saw 2.5 ms).
  EXPECT_GE(abort_after_ms, 1000.0 - 5.0) << "not before the consumer time";
  // Slack: the master's loop and candump under user-mode Linux on a busy host.
  EXPECT_LE(abort_after_ms, 1000.0 + 500.0) << "within the consumer time, long before the 10 s SDO timeout";

  EXPECT_EQ(master.wait_exit(kVcanDeadline), 4) << master.stderr_text();
  const std::string err = master.stderr_text();
  EXPECT_NE(
      err.find(
          "node 5 1F50h/1: node lost (no heartbeat within the consumer time), transfer aborted 05040000h"),
      std::string::npos)
      << err;
  const std::vector<uint8_t> pattern = program_data_pattern();
  EXPECT_TRUE(file_bytes(dir.path("up.4")) == pattern) << "node 4's transfer finished\n" << err;
  EXPECT_TRUE(file_bytes(dir.path("up.6")) == pattern) << "node 6's transfer finished\n" << err;
  EXPECT_TRUE(file_bytes(dir.path("up.5")).empty()) << "nothing half-written for node 5";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
