// mb2co-master --via-modbus tcp:HOST:PORT against a 3-station ring on vcan0:
// node 1 is the gateway, serving Modbus/TCP (--tcp) beside its pty; nodes 2
// and 3 are only on CAN. Each command runs over SocketCAN and through the
// gateway on TCP and must print the same bytes and exit alike (scan finds
// all three, read/write agree, a 600-byte object goes in parts:
// via_modbus_ring.h, the checks of the serial way too); two masters through
// the one gateway at once both finish with what each prints alone (one
// remote transfer at a time: a 2Bh/0Dh meanwhile gets 06, the master
// retries); a port with no gateway is exit 3. ctest runs this binary inside
// hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>

#include "via_modbus_ring.h"

namespace mb2co {
namespace test {
namespace {

/// The ring (via_modbus_ring.h), the gateway reached on Modbus/TCP.
class ViaModbusTcp : public ViaModbusRing {
 protected:
  static void SetUpTestSuite() {
    start_ring({"--tcp", "127.0.0.1:0"});
    via_ = [] { return "tcp:" + nodes_[0]->tcp_address(); };
  }
};

TEST_F(ViaModbusTcp, ScanFindsAllThreeStations) {
  scan_finds_all_three();
}

TEST_F(ViaModbusTcp, ReadAndWriteAgreeWithSocketCan) {
  read_and_write_agree();
}

TEST_F(ViaModbusTcp, ALongObjectGoesInParts) {
  long_objects_go_in_parts();
}

TEST_F(ViaModbusTcp, TwoMastersThroughOneGatewayAtOnce) {
  const MasterRun scan_alone = run_master({"scan", "1", "4"});
  const MasterRun read_alone = run_master({"read", "2,3", "1008", "0", "vs"});
  LineChild first, second;
  ASSERT_TRUE(start_master(&first, via({"scan", "1", "4"})));
  ASSERT_TRUE(start_master(&second, via({"read", "2,3", "1008", "0", "vs"})));
  auto finish = [](LineChild& c) {
    MasterRun run;
    c.close_stdin();
    std::string line;
    while (c.wait_line([](const std::string&) { return true; }, kVcanDeadline, &line))
      run.out.push_back(line);
    run.exit_code = c.wait_exit(kVcanDeadline);
    run.err = c.stderr_text();
    return run;
  };
  const MasterRun a = finish(first), b = finish(second);
  EXPECT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(a.text(), scan_alone.text()) << "the same as over SocketCAN alone";
  EXPECT_EQ(b.text(), read_alone.text());
}

TEST_F(ViaModbusTcp, NoGatewayOnThePortIsExit3) {
  // A port nobody serves.
  const MasterRun run = run_master({"--via-modbus", "tcp:127.0.0.1:1", "read", "2", "1000", "0", "u32"});
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_EQ(run.err, "mb2co-master: cannot connect to tcp:127.0.0.1:1: Connection refused\n");
}

}  // namespace
}  // namespace test
}  // namespace mb2co
