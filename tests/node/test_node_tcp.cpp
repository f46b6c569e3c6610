// Modbus/TCP of mb2co-node (docs/mb2co-node.md "Modbus/TCP") on the host,
// without CAN (--can none): clients that are not ours (libmodbus's TCP
// backend, mbpoll -m tcp) on every function code, beside the pty whose
// registers are the same; raw frames for what the Modbus Messaging on
// TCP/IP Implementation Guide leaves to the server: unit ids, pipelined
// transactions of two clients, garbage, lengths outside 2..254, a foreign
// protocol id, half frames, the connection limit, FC 08; the line
// application's watchdog fed by a PC on TCP; the command line.
#include <errno.h>
#include <gtest/gtest.h>
#include <modbus.h>

#include <algorithm>
#include <thread>

#include "mbpoll_run.h"
#include "node_harness.h"
#include "tcp_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kHrRunCommand = 0, kHrLabLed = 1, kHrDebounce = 7, kHrCyclePeriod = 9;
constexpr int kCoilRunCommand = 0;
constexpr int kIrRunState = 1, kIrStopCause = 3, kIrNmt = 22;
constexpr int kDiRunState = 3;
constexpr int kTcpClients = 3;  // the fixture's limit, small enough to reach

// The PDU of an FC 03 of one holding register, and its answer for `value`.
TcpBytes read_hr(uint16_t reg) {
  return {0x03, static_cast<uint8_t>(reg >> 8), static_cast<uint8_t>(reg), 0x00, 0x01};
}
TcpBytes hr_value(uint16_t value) {
  return {0x03, 0x02, static_cast<uint8_t>(value >> 8), static_cast<uint8_t>(value)};
}

class NodeTcp : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(node_.start({"--can", "none", "--pty", dir_.path("node.pty"), "--tcp", "127.0.0.1:0",
                             "--tcp-clients", std::to_string(kTcpClients)}))
        << node_.error();
    ASSERT_FALSE(node_.tcp_address().empty()) << "the ready line names the port";
    ASSERT_TRUE(line_.open(node_.device())) << line_.error();
  }
  void TearDown() override {
    if (tcp_ != nullptr) {
      modbus_close(tcp_);
      modbus_free(tcp_);
    }
    line_.close();
    EXPECT_EQ(node_.stop(), 0);
  }
  std::string host() const { return node_.tcp_address().substr(0, node_.tcp_address().rfind(':')); }
  std::string port() const { return node_.tcp_address().substr(node_.tcp_address().rfind(':') + 1); }
  /// A libmodbus TCP context on the node, unit id 0xFF (MODBUS_TCP_SLAVE).
  modbus_t* libmodbus_tcp() {
    tcp_ = modbus_new_tcp(host().c_str(), std::stoi(port()));
    if (tcp_ == nullptr || modbus_connect(tcp_) != 0) return nullptr;
    modbus_set_response_timeout(tcp_, 2, 0);
    return tcp_;
  }
  TcpPeer& peer(TcpPeer& p) {
    EXPECT_TRUE(p.connect(node_.tcp_address()));
    return p;
  }

  TempDir dir_;
  NodeProcess node_;
  ModbusMaster line_;  // libmodbus RTU on the node's pty
  modbus_t* tcp_ = nullptr;
};

TEST_F(NodeTcp, LibmodbusEveryFunctionCodeOnTheLinesRegisters) {
  modbus_t* c = libmodbus_tcp();
  ASSERT_NE(c, nullptr) << modbus_strerror(errno);
  ASSERT_EQ(modbus_write_bit(c, kCoilRunCommand, 1), 1);  // FC 05
  EXPECT_EQ(line_.holding_register(kHrRunCommand), 1) << "the line reads what TCP wrote";
  ASSERT_EQ(modbus_write_register(c, kHrDebounce, 35), 1);  // FC 06
  EXPECT_EQ(line_.holding_register(kHrDebounce), 35);
  const uint8_t coils[2] = {1, 1};
  ASSERT_EQ(modbus_write_bits(c, 0, 2, coils), 2);  // FC 0F
  EXPECT_EQ(line_.holding_register(kHrLabLed), 1);
  const uint16_t period[2] = {0x0001, 0x86A0};                         // 100000 us, high word first
  ASSERT_EQ(modbus_write_registers(c, kHrCyclePeriod, 2, period), 2);  // FC 10
  uint16_t hr[2] = {};
  ASSERT_EQ(modbus_read_registers(c, kHrCyclePeriod, 2, hr), 2);  // FC 03
  EXPECT_EQ(hr[0], 1);
  EXPECT_EQ(hr[1], 0x86A0);
  const uint16_t debounce = 40;
  uint16_t back = 0;
  ASSERT_EQ(modbus_write_and_read_registers(c, kHrDebounce, 1, &debounce, kHrDebounce, 1, &back),
            1);  // FC 17
  EXPECT_EQ(back, 40);
  uint16_t ir[23] = {};
  ASSERT_EQ(modbus_read_input_registers(c, 0, 23, ir), 23);  // FC 04
  EXPECT_EQ(ir[kIrRunState], 1);
  EXPECT_EQ(ir[kIrNmt], 5);
  uint8_t bits[7] = {};
  ASSERT_EQ(modbus_read_bits(c, 0, 2, bits), 2);  // FC 01
  EXPECT_EQ(bits[0], 1);
  ASSERT_EQ(modbus_read_input_bits(c, 0, 7, bits), 7);  // FC 02
  EXPECT_EQ(bits[kDiRunState], 1);
  EXPECT_EQ(modbus_read_registers(c, 20, 1, hr), -1);  // past the map
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_write_register(c, kHrRunCommand, 2), -1);  // RUN command 2: refused by the entry
  EXPECT_EQ(errno, EMBXSFAIL);
}

TEST_F(NodeTcp, LibmodbusRawRequestsForDeviceIdAndTheLocalNetworkService) {
  modbus_t* c = libmodbus_tcp();
  ASSERT_NE(c, nullptr) << modbus_strerror(errno);
  // FC 2B/0E basic device identification, then FC 2B/0D (docs/gateway-network.md):
  // an SDO upload of 1018h/1 (vendor id) from the gateway's own node 1,
  // served from its OD without the bus.
  const TcpBytes requests[2] = {
      {0xFF, 0x2B, 0x0E, 0x01, 0x00},
      {0xFF, 0x2B, 0x0D, 0x00, 0x00, 0x01, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00}};
  TcpBytes answers[2];
  for (int i = 0; i < 2; ++i) {
    ASSERT_GT(modbus_send_raw_request(c, requests[i].data(), static_cast<int>(requests[i].size())), 0);
    // Read off libmodbus's socket here: it cannot receive FC 2Bh.
    const TcpBytes f = TcpPeer::read_frame(modbus_get_socket(c));
    ASSERT_GE(f.size(), 8u) << "request " << i;
    // libmodbus 3.1.6 sends a raw request as transaction 0 (its function
    // calls number theirs and check the echo themselves).
    EXPECT_EQ(f[0] << 8 | f[1], 0) << "transaction id echoed";
    EXPECT_EQ(f[6], 0xFF) << "unit id echoed";
    answers[i].assign(f.begin() + 7, f.end());
  }
  const std::string identity(answers[0].begin(), answers[0].end());
  EXPECT_NE(identity.find("mb2co"), std::string::npos);
  // The same request on the line gets the same PDU.
  const Bytes line = line_.raw_transaction(Bytes(requests[1].begin() + 1, requests[1].end()));
  ASSERT_FALSE(line.empty());
  EXPECT_EQ(answers[1], TcpBytes(line.begin() + 1, line.end()));
  EXPECT_EQ(answers[1].size(), 20u) << "header, object size 4, the vendor id";
}

TEST_F(NodeTcp, MbpollTcpEveryTable) {
  auto mbpoll = [&](const std::vector<std::string>& options, const std::vector<std::string>& values = {}) {
    std::vector<std::string> argv{"mbpoll", "-m", "tcp", "-p", port(), "-a", "1", "-0", "-1", "-o", "1"};
    argv.insert(argv.end(), options.begin(), options.end());
    argv.push_back(host());
    argv.insert(argv.end(), values.begin(), values.end());
    return run_mbpoll(argv);
  };
  auto read = [&](const std::string& table, int ref, int count) {
    const MbpollRun r = mbpoll({"-t", table, "-r", std::to_string(ref), "-c", std::to_string(count)});
    EXPECT_EQ(r.status, 0) << r.output;
    return r.values;
  };
  auto write = [&](const std::string& table, int ref, const std::vector<std::string>& values) {
    const MbpollRun r = mbpoll({"-t", table, "-r", std::to_string(ref)}, values);
    EXPECT_EQ(r.status, 0) << r.output;
  };
  using Values = std::vector<std::string>;
  write("4", kHrRunCommand, {"1", "1"});           // FC 10
  EXPECT_EQ(read("4", 0, 2), (Values{"1", "1"}));  // FC 03
  EXPECT_EQ(line_.holding_register(kHrLabLed), 1) << "the same register on the line";
  EXPECT_EQ(read("0", 0, 2), (Values{"1", "1"}));       // FC 01
  EXPECT_EQ(read("3", kIrRunState, 1), (Values{"1"}));  // FC 04
  EXPECT_EQ(read("1", kDiRunState, 1), (Values{"1"}));  // FC 02
  write("0", 1, {"0"});                                 // FC 05
  EXPECT_EQ(line_.holding_register(kHrLabLed), 0);
  write("0", 0, {"1", "1"});  // FC 0F
  EXPECT_EQ(line_.holding_register(kHrLabLed), 1);
  write("4", kHrDebounce, {"35"});  // FC 06
  EXPECT_EQ(line_.holding_register(kHrDebounce), 35);
  const MbpollRun wide = mbpoll({"-t", "4:int", "-B", "-r", std::to_string(kHrCyclePeriod)}, {"100000"});
  EXPECT_EQ(wide.status, 0) << wide.output;  // FC 10, one 32-bit value
  EXPECT_EQ(line_.holding_register(kHrCyclePeriod), 1) << "high word first";
  EXPECT_EQ(line_.holding_register(kHrCyclePeriod + 1), 34464);
  const MbpollRun r = mbpoll({"-t", "4", "-r", "20", "-c", "1"});
  EXPECT_NE(r.output.find("Illegal data address"), std::string::npos) << r.output;
}

TEST_F(NodeTcp, AnyUnitIdIsAnsweredAndEchoed) {
  TcpPeer p;
  peer(p);
  for (unsigned unit : {0u, 1u, 42u, 247u, 255u}) {
    EXPECT_EQ(p.ask(static_cast<uint16_t>(0x4100 + unit), static_cast<uint8_t>(unit), read_hr(kHrDebounce)),
              hr_value(20))
        << "unit " << unit << ": as libmodbus's TCP server, not a broadcast";
  }
}

TEST_F(NodeTcp, TwoClientsPipelineTheirTransactionsAndEachGetsItsOwn) {
  TcpPeer a, b;
  peer(a);
  peer(b);
  TcpBytes burst_a, burst_b;
  for (uint16_t i = 0; i < 8; ++i) {
    const TcpBytes fa = mbap(static_cast<uint16_t>(0xA000 + i), 0xFF, read_hr(kHrDebounce));
    const TcpBytes fb = mbap(static_cast<uint16_t>(0xB000 + i), 0x01, {0x04, 0x00, kIrNmt, 0x00, 0x01});
    burst_a.insert(burst_a.end(), fa.begin(), fa.end());
    burst_b.insert(burst_b.end(), fb.begin(), fb.end());
  }
  ASSERT_TRUE(a.send(burst_a));  // both in flight before either reads
  ASSERT_TRUE(b.send(burst_b));
  for (uint16_t i = 0; i < 8; ++i) {
    const TcpBytes fa = a.frame();
    const TcpBytes fb = b.frame();
    EXPECT_EQ(fa, mbap(static_cast<uint16_t>(0xA000 + i), 0xFF, hr_value(20))) << i;
    EXPECT_EQ(fb, mbap(static_cast<uint16_t>(0xB000 + i), 0x01, {0x04, 0x02, 0x00, 0x05})) << i;
  }
  EXPECT_TRUE(a.silent_for(100ms)) << "one answer per request";
}

TEST_F(NodeTcp, GarbageOrALengthOutside2To254ClosesThatConnectionOnly) {
  TcpPeer good;
  peer(good);
  ASSERT_EQ(good.ask(1, 0xFF, read_hr(kHrDebounce)), hr_value(20));
  const std::string http = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";  // length field 0x2F20
  const TcpBytes bad[] = {TcpBytes(http.begin(), http.end()),
                          {0x00, 0x01, 0x00, 0x00, 0xFF, 0xFF, 0x01, 0x03},  // claims 65535 bytes
                          {0x00, 0x01, 0x00, 0x00, 0x00, 0xFF, 0x01},        // 255: one beyond a PDU of 253
                          {0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x01}};       // 1: no function code
  for (const TcpBytes& b : bad) {
    TcpPeer p;
    peer(p);
    ASSERT_TRUE(p.send(b));
    EXPECT_TRUE(p.closed_by_server()) << "bytes " << b.size();
    EXPECT_EQ(good.ask(2, 0xFF, read_hr(kHrDebounce)), hr_value(20)) << "the other connection is served";
  }
  // The longest frame (length 254, a PDU of 253 bytes) is served: FC 08 with
  // 250 data bytes gets exception 01 on TCP. FC 10 of 123 registers (252
  // bytes), past the map, gets exception 02.
  TcpBytes longest = {0x08, 0x00, 0x00};
  longest.resize(253, 0x5A);
  ASSERT_EQ(mbap(3, 0xFF, longest).size(), 260u);
  EXPECT_EQ(good.ask(3, 0xFF, longest), (TcpBytes{0x88, 0x01}));
  TcpBytes write = {0x10, 0x00, 0x00, 0x00, 123, 246};
  write.resize(write.size() + 246, 0x00);
  EXPECT_EQ(good.ask(4, 0xFF, write), (TcpBytes{0x90, 0x02}));
}

TEST_F(NodeTcp, AFrameOfAnotherProtocolIsSkippedAndTheStreamGoesOn) {
  TcpPeer p;
  peer(p);
  TcpBytes two = mbap(0x0101, 0xFF, read_hr(kHrDebounce), 0x0001);  // protocol id 1
  const TcpBytes modbus = mbap(0x0202, 0xFF, read_hr(kHrDebounce));
  two.insert(two.end(), modbus.begin(), modbus.end());
  ASSERT_TRUE(p.send(two));
  EXPECT_EQ(p.frame(), mbap(0x0202, 0xFF, hr_value(20))) << "only the Modbus frame is answered";
  EXPECT_TRUE(p.silent_for(100ms));
}

TEST_F(NodeTcp, AHalfFrameHoldsNoOneUp) {
  TcpPeer slow, quick;
  peer(slow);
  peer(quick);
  const TcpBytes f = mbap(0x0303, 0xFF, read_hr(kHrDebounce));
  ASSERT_TRUE(slow.send(TcpBytes(f.begin(), f.begin() + 5)));  // part of the header
  EXPECT_EQ(quick.ask(1, 0xFF, read_hr(kHrDebounce)), hr_value(20));
  ASSERT_TRUE(slow.send(TcpBytes(f.begin() + 5, f.begin() + 9)));
  EXPECT_EQ(quick.ask(2, 0xFF, read_hr(kHrDebounce)), hr_value(20));
  ASSERT_TRUE(slow.send(TcpBytes(f.begin() + 9, f.end())));
  EXPECT_EQ(slow.frame(), mbap(0x0303, 0xFF, hr_value(20))) << "completed late, answered";
}

TEST_F(NodeTcp, AtTheLimitANewConnectionTakesThePlaceOfTheOldestUnused) {
  TcpPeer c[kTcpClients + 1];
  for (int i = 0; i < kTcpClients; ++i) {
    peer(c[i]);
    ASSERT_EQ(c[i].ask(static_cast<uint16_t>(i), 0xFF, read_hr(kHrDebounce)), hr_value(20)) << i;
  }
  peer(c[kTcpClients]);
  EXPECT_EQ(c[kTcpClients].ask(9, 0xFF, read_hr(kHrDebounce)), hr_value(20)) << "the newest is served";
  EXPECT_TRUE(c[0].closed_by_server()) << "the one unused longest made room";
  for (int i = 1; i <= kTcpClients; ++i)
    EXPECT_EQ(c[i].ask(10, 0xFF, read_hr(kHrDebounce)), hr_value(20)) << i << " kept";
}

TEST_F(NodeTcp, DiagnosticsAreTheSerialLinesOnly) {
  TcpPeer p;
  peer(p);
  EXPECT_EQ(p.ask(1, 0xFF, {0x08, 0x00, 0x00, 0xA5, 0x5A}), (TcpBytes{0x88, 0x01})) << "exception 01";
  EXPECT_EQ(line_.raw_transaction({0x08, 0x00, 0x00, 0xA5, 0x5A}),
            (Bytes{0x01, 0x08, 0x00, 0x00, 0xA5, 0x5A}))
      << "the line echoes";
  EXPECT_EQ(line_.diag_counter(0x0E), 3u)
      << "CPT4 counts the TCP request, the echo and itself (the watchdog's count)";
}

TEST_F(NodeTcp, AStationRunFromTcpAloneKeepsItsWatchdogFed) {
  TcpPeer pc;
  peer(pc);
  ASSERT_EQ(pc.ask(1, 0xFF, {0x06, 0x00, kHrRunCommand, 0x00, 0x01}),
            (TcpBytes{0x06, 0x00, 0x00, 0x00, 0x01}));
  // Past the watchdog's 2 s (2000h/9) with requests on TCP only, as a PC
  // polling every 100 ms would (pacing, not synchronisation).
  const auto until = std::chrono::steady_clock::now() + 2500ms;
  uint16_t t = 2;
  while (std::chrono::steady_clock::now() < until) {
    ASSERT_EQ(pc.ask(t++, 0xFF, {0x04, 0x00, kIrStopCause, 0x00, 0x01}), (TcpBytes{0x04, 0x02, 0x00, 0x00}))
        << "no stop cause: the watchdog saw the requests";
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(pc.ask(t, 0xFF, {0x04, 0x00, kIrRunState, 0x00, 0x01}), (TcpBytes{0x04, 0x02, 0x00, 0x01}));
}

// The command line (no fixture: each run is its own node).
TEST(NodeTcpCli, TcpOnlyBadAddressesAndAPortInUse) {
  NodeProcess only;
  ASSERT_TRUE(only.start({"--can", "none", "--serial", "none", "--tcp", "0"})) << only.error();
  EXPECT_EQ(only.device(), "none") << "no serial line";
  EXPECT_EQ(only.tcp_address().rfind("127.0.0.1:", 0), 0u)
      << "a bare port is localhost: " << only.tcp_address();
  TcpPeer p;
  ASSERT_TRUE(p.connect(only.tcp_address()));
  EXPECT_EQ(p.ask(1, 0xFF, read_hr(kHrDebounce)), hr_value(20));

  struct Case {
    std::vector<std::string> args;
    int status;
    std::string says;
  };
  const Case cases[] = {
      {{"--tcp", "127.0.0.1:99999"}, 2, "port 99999 is outside 0..65535"},
      {{"--tcp", "localhost:"}, 2, "want HOST:PORT"},
      {{"--tcp", "::1:502"}, 2, "want HOST:PORT"},
      {{"--tcp-clients", "4"}, 2, "--tcp-clients needs --tcp"},
      {{"--tcp", "0", "--tcp-clients", "33"}, 2, "--tcp-clients"},
      {{"--tcp", only.tcp_address()}, 1, "Address already in use"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> argv{node_program(), "--can", "none", "--serial", "none"};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    LineChild run;
    ASSERT_TRUE(run.start(argv));
    run.close_stdin();
    EXPECT_EQ(run.wait_exit(10s), c.status) << c.args.back();
    const std::string err = run.stderr_text();
    EXPECT_NE(err.find(c.says), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << "one line: " << err;
  }
  EXPECT_EQ(only.stop(), 0);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
