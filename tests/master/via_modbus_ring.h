// The ring the --via-modbus tests run against: 3 stations on vcan0
// (--stations 3: every station has both neighbours, so no LED blinks for a
// missing one and a dump holds still), node 1 the gateway on its pty (and on
// Modbus/TCP when the binary asks), nodes 2 and 3 only on CAN. Started once
// per test binary (a node takes a while to come up in user-mode Linux).
// Every command of a test can run both ways, over SocketCAN and through the
// gateway, which must print the same bytes and exit alike.
#pragma once
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "master_cli.h"
#include "node_harness.h"

namespace mb2co {
namespace test {

/// The whole file ("" when it cannot be read).
inline std::string file_text(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

class ViaModbusRing : public ::testing::Test {
 protected:
  /// Starts the ring; node 1 gets `gateway_extra` too ("--tcp", ...).
  static void start_ring(const std::vector<std::string>& gateway_extra = {}) {
    dir_ = new TempDir;
    for (int i = 0; i < 3; ++i) {
      const std::string n = std::to_string(1 + i);
      std::vector<std::string> args{"--can",      "vcan0", "--node-id", n,
                                    "--stations", "3",     "--pty",     dir_->path("st" + n)};
      if (i == 0) args.insert(args.end(), gateway_extra.begin(), gateway_extra.end());
      nodes_[i] = new NodeProcess;
      if (!nodes_[i]->start(args, kVcanDeadline)) failure_ += "node " + n + ": " + nodes_[i]->error() + "; ";
    }
  }
  static void TearDownTestSuite() {
    for (NodeProcess*& n : nodes_) {
      delete n;
      n = nullptr;
    }
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(failure_.empty()) << failure_; }

  /// `args` through the gateway: --via-modbus and what via_ says.
  static std::vector<std::string> via(std::vector<std::string> args) {
    args.insert(args.begin(), {"--via-modbus", via_()});
    return args;
  }
  /// Runs `args` over SocketCAN and through the gateway; both runs must
  /// agree byte for byte (stdout, stderr; but a dump's 1013h, the node's
  /// clock) and in the exit code. Returns the
  /// SocketCAN run.
  static MasterRun both(const std::vector<std::string>& args) {
    const MasterRun can = run_master(args);
    const MasterRun gw = run_master(via(args));
    std::string what;
    for (const std::string& a : args) what += a + " ";
    EXPECT_EQ(gw.exit_code, can.exit_code) << what << "\ngateway: " << gw.err << "\nSocketCAN: " << can.err;
    EXPECT_EQ(without_clock(gw.text()), without_clock(can.text())) << what;  // a dump's 1013h: its instant
    EXPECT_EQ(gw.err, can.err) << what;
    return can;
  }

  // The checks every way to the gateway must pass (each binary's TEST_Fs).
  /// scan 1 6 finds the three stations, alike both ways.
  static void scan_finds_all_three() {
    const MasterRun run = both({"scan", "1", "6"});
    EXPECT_EQ(run.exit_code, 0) << run.err;
    for (int id = 1; id <= 3; ++id)
      EXPECT_NE(run.text().find("node " + std::to_string(id) + ": device type"), std::string::npos)
          << run.text();
    EXPECT_NE(run.text().find("scan: 3 of 6 node ids answered"), std::string::npos) << run.text();
  }
  /// read and write agree with SocketCAN, values cross both ways, refusals alike.
  static void read_and_write_agree() {
    EXPECT_EQ(both({"read", "2", "1018", "1", "u32"}).exit_code, 0);
    EXPECT_EQ(both({"read", "1", "1018", "2", "u32"}).exit_code, 0);   // the gateway's own OD
    EXPECT_EQ(both({"read", "2,3", "1008", "0", "vs"}).exit_code, 0);  // segmented, two nodes
    EXPECT_EQ(both({"--json", "read", "3", "1017", "0", "u16"}).exit_code, 0);

    // Written through the gateway, read back over SocketCAN, and the reverse.
    const MasterRun w = run_master(via({"write", "3", "1017", "0", "u16", "750"}));
    EXPECT_EQ(w.exit_code, 0) << w.err;
    EXPECT_EQ(w.text(), "node 3 1017h/0: 2 bytes written\n");
    EXPECT_EQ(run_master({"read", "3", "1017", "0", "u16"}).text(), "0x2EE\n");  // 750
    ASSERT_EQ(run_master({"write", "3", "1017", "0", "u16", "1000"}).exit_code, 0);
    EXPECT_EQ(run_master(via({"read", "3", "1017", "0", "u16"})).text(), "0x3E8\n");  // 1000
    EXPECT_EQ(both({"write", "2", "1017", "0", "u16", "1000"}).exit_code, 0);

    // Refusals and silence: the same line, the same exit code.
    EXPECT_EQ(both({"write", "2", "1000", "0", "u32", "5"}).exit_code, 1);         // read only
    EXPECT_EQ(both({"read", "2", "2FFF", "0", "u8"}).exit_code, 1);                // no such object
    EXPECT_EQ(both({"-t", "500", "read", "9", "1000", "0", "u32"}).exit_code, 4);  // nobody there
  }
  /// A 600-byte object in windows and parts, the same bytes both ways.
  static void long_objects_go_in_parts() {
    // 1F50h/1 (a DOMAIN) takes a 600-byte file: three parts through the
    // gateway, the same bytes come back over SocketCAN and through it.
    std::string bytes;
    for (int i = 0; i < 600; ++i) bytes += static_cast<char>((i * 7 + 3) & 0xFF);
    const std::string in = dir_->path("in.bin"), via_can = dir_->path("can.bin"),
                      via_gw = dir_->path("gw.bin");
    {
      std::ofstream f(in, std::ios::binary);
      f << bytes;
    }
    const MasterRun down = run_master(via({"download", "2", "1F50", "1", in}));
    ASSERT_EQ(down.exit_code, 0) << down.err;
    ASSERT_EQ(run_master({"upload", "2", "1F50", "1", via_can}).exit_code, 0);
    EXPECT_EQ(file_text(via_can), bytes);
    const MasterRun up = run_master(via({"upload", "2", "1F50", "1", via_gw}));
    ASSERT_EQ(up.exit_code, 0) << up.err;
    EXPECT_EQ(file_text(via_gw), bytes);
  }

  /// The --via-modbus value of the gateway (set by the binary's fixture).
  static inline std::string (*via_)() = nullptr;
  static inline TempDir* dir_ = nullptr;
  static inline NodeProcess* nodes_[3] = {};
  static inline std::string failure_;
};

}  // namespace test
}  // namespace mb2co
