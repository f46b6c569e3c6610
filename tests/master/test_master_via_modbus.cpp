// mb2co-master --via-modbus against a 3-station ring on vcan0 (--stations 3:
// every station has both neighbours, so no LED blinks for a missing one and
// a dump holds still): node 1 is the gateway, reached over its pty (FC
// 2Bh/MEI 0Dh), nodes 2 and 3 are only on CAN. Every command runs both ways,
// through the gateway and over SocketCAN, and must print the same bytes and
// exit with the same code (issue 12's must-show: scan finds all three, a
// dump of a remote node equals the dump over SocketCAN, read/write/nmt
// agree). candump is the witness that NMT through the gateway reached the
// line. ctest runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "eds_reader.h"
#include "eds_value.h"
#include "eds_writer.h"
#include "via_modbus_ring.h"

namespace mb2co {
namespace test {
namespace {

const char* const kEds = MB2CO_GATEWAY_EDS;

/// The ring (via_modbus_ring.h), the gateway reached over its pty.
class ViaModbus : public ViaModbusRing {
 protected:
  static void SetUpTestSuite() {
    start_ring();
    via_ = [] { return nodes_[0]->device() + ":1"; };  // PORT:1, PORT the gateway's pty
  }
};

TEST_F(ViaModbus, ScanFindsAllThreeStations) {
  scan_finds_all_three();
}

TEST_F(ViaModbus, DumpOfARemoteNodeEqualsTheDumpOverSocketCan) {
  // A value that is not the EDS default, so both dumps must have uploaded it.
  ASSERT_EQ(run_master({"write", "2", "1017", "0", "u16", "1500"}).exit_code, 0);
  const MasterRun to_stdout = both({"--eds", kEds, "dump", "2"});
  EXPECT_EQ(to_stdout.exit_code, 0) << to_stdout.err;
  EXPECT_NE(to_stdout.text().find("ParameterValue=0x5DC"), std::string::npos)
      << "1017h = 1500 not in the DCF";

  const std::string over_can = dir_->path("can.dcf"), through_gw = dir_->path("gw.dcf");
  const MasterRun can = run_master({"--eds", kEds, "dump", "2", over_can});
  const MasterRun gw = run_master(via({"--eds", kEds, "dump", "2", through_gw}));
  ASSERT_EQ(can.exit_code, 0) << can.err;
  ASSERT_EQ(gw.exit_code, 0) << gw.err;
  EXPECT_EQ(gw.text(), can.text());
  EXPECT_FALSE(file_text(over_can).empty());
  EXPECT_EQ(without_clock(file_text(through_gw)), without_clock(file_text(over_can)));
}

TEST_F(ViaModbus, ReadAndWriteAgreeWithSocketCan) {
  read_and_write_agree();
}

TEST_F(ViaModbus, LongObjectsGoInWindowsAndParts) {
  long_objects_go_in_parts();
}

TEST_F(ViaModbus, NmtThroughTheGatewayReachesTheLine) {
  LineChild candump;
  ASSERT_TRUE(start_candump(&candump));
  /// Waits for node 2's heartbeat saying `state`.
  const auto heartbeat = [&](unsigned state) {
    return candump.wait_line(
        [state](const std::string& line) {
          unsigned id = 0;
          std::vector<unsigned> data;
          return parse_candump(line, &id, &data) && id == 0x702 && data.size() == 1 && data[0] == state;
        },
        kVcanDeadline);
  };
  MasterRun run = run_master(via({"nmt", "stop", "2"}));
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.text(), "nmt stop 2\n");
  EXPECT_TRUE(heartbeat(0x04)) << "node 2 never said stopped";
  run = run_master(via({"nmt", "start", "all"}));
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.text(), "nmt start all\n");
  EXPECT_TRUE(heartbeat(0x05)) << "node 2 never said operational";
  // The same words and exit code as over SocketCAN.
  EXPECT_EQ(both({"--json", "nmt", "preop", "3"}).exit_code, 0);
  EXPECT_EQ(both({"nmt", "start", "3"}).exit_code, 0);
}

TEST_F(ViaModbus, ConfigureThroughTheGatewayThenBothWaysAgree) {
  // Node 3's DCF: heartbeat, debounce, TPDO1 event timer (a PDO parameter:
  // configure invalidates the PDO around it, more requests in order).
  eds::ParseResult parsed = eds::parse_file(kEds);
  ASSERT_TRUE(parsed) << parsed.error.text();
  eds::DeviceDescription model = *parsed.model;
  const struct {
    uint16_t index;
    uint8_t sub;
    const char* value;
  } settings[] = {{0x1017, 0, "1200"}, {0x2000, 6, "0x20"}, {0x1800, 5, "500"}};
  for (const auto& s : settings)
    for (eds::SubObject& x : model.objects[s.index].subs)
      if (x.sub == s.sub) x.parameter_value = eds::parse_value(x.type, s.value).value;
  {
    std::ofstream f(dir_->path("node3.dcf"), std::ios::binary);
    f << eds::write_dcf(model, 3);
    std::ofstream n(dir_->path("net.cpj"), std::ios::binary);
    n << "[Topology]\nNodes=1\nNode3Present=1\nNode3DCFName=node3.dcf\n";
  }
  const MasterRun first = run_master(via({"configure", dir_->path("net.cpj")}));
  EXPECT_EQ(first.exit_code, 0) << first.err;
  EXPECT_EQ(first.text(), "node 3: configured: 3 written, 0 equal, 0 read-only skipped, started\n");
  EXPECT_EQ(run_master({"read", "3", "1017", "0", "u16"}).text(), "0x4B0\n");  // 1200, over SocketCAN
  const MasterRun again = both({"configure", dir_->path("net.cpj")});
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.text(), "node 3: configured: 0 written, 3 equal, 0 read-only skipped, started\n");
}

TEST_F(ViaModbus, RawCanCommandsAreUsageErrors) {
  for (const std::vector<std::string>& args : {std::vector<std::string>{"watch"},
                                               {"sync"},
                                               {"upload", "2", "1F50", "1", "/dev/null", "--block"},
                                               {"--watchdog", "500", "read", "2", "1000", "0"}}) {
    const MasterRun run = run_master(via(args));
    EXPECT_EQ(run.exit_code, 2) << args[0];
    EXPECT_TRUE(run.out.empty());
    EXPECT_NE(run.err.find("needs raw CAN frames: not through a gateway (--via-modbus)"), std::string::npos)
        << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << "one line: " << run.err;
  }
}

TEST_F(ViaModbus, NoGatewayOnThePortIsExit3) {
  // Node 2's pty: a Modbus slave at address 1, but ask address 9 (nobody).
  const MasterRun run =
      run_master({"-t", "200", "--via-modbus", nodes_[1]->device() + ":9", "read", "2", "1000", "0", "u32"});
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("no answer from slave 9 on " + nodes_[1]->device()), std::string::npos) << run.err;
}

}  // namespace
}  // namespace test
}  // namespace mb2co
