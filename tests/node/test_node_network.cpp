// FC 2Bh / MEI 0Dh against mb2co-node on vcan0 (ctest runs this binary inside
// hil/uml/run-with-vcan.sh): a libmodbus master on the pty of node 1 (the
// gateway) reaches node 2 (a second mb2co-node) over CAN; candump records
// the bus. The requests are bytes written here from docs/gateway-network.md
// and sent with modbus_send_raw_request; libmodbus 3.1.6 cannot receive a
// 2Bh response (it takes its length from the function code: checked below),
// so the responses are read from the serial fd (tests/support's
// read_response) and checked byte by byte here, not with shared/modbus.
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string>

#include "node_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kUmlDeadline = 60s;  // bounds a failure only
// The SDO client's time per step (docs/gateway-network.md): a missing node
// is answered with abort 05040000h after it. Under user-mode Linux on a
// shared host a process may wait ~100 ms for the CPU: the upper bound has
// that slack, the lower none.
constexpr auto kSdoTimeout = 500ms;
constexpr auto kSlack = 250ms;

class NodeNetwork : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    candump_ = new LineChild;
    const Status listening = start_candump_listening(*candump_, kUmlDeadline);
    ASSERT_TRUE(listening) << listening.message();
    for (int i = 0; i < 2; ++i) {
      const std::string id = std::to_string(i + 1);
      node_[i] = new NodeProcess;
      ASSERT_TRUE(node_[i]->start({"--can", "vcan0", "--node-id", id, "--pty", dir_->path(id + ".pty")},
                                  kUmlDeadline))
          << node_[i]->error();
    }
    master_ = new ModbusMaster;
    ASSERT_TRUE(master_->open(node_[0]->device(), 2s)) << master_->error();
  }
  static void TearDownTestSuite() {
    delete master_;
    for (NodeProcess*& n : node_) {
      delete n;
      n = nullptr;
    }
    delete candump_;
    delete dir_;
  }

  // Sends `pdu` to slave 1 with libmodbus (raw) and reads the response PDU.
  static Bytes transact(const Bytes& pdu, std::chrono::milliseconds timeout = 2s) {
    send(pdu);
    // read_response knows FC 2Bh/0Dh's lengths from docs/gateway-network.md.
    const Bytes adu = read_response(master_->fd(), pdu.size(), timeout);
    if (adu.empty() || adu[0] != 1u) return {};
    return Bytes(adu.begin() + 1, adu.end());
  }
  static void send(const Bytes& pdu) {
    Bytes req{1};
    req.insert(req.end(), pdu.begin(), pdu.end());
    ASSERT_GT(modbus_send_raw_request(master_->ctx(), req.data(), static_cast<int>(req.size())), 0);
  }
  // An upload request (docs/gateway-network.md, "SDO upload").
  static Bytes upload(uint8_t node, uint16_t index, uint8_t sub, uint16_t start = 0, uint16_t count = 0) {
    return {0x2B,
            0x0D,
            0x00,
            0x00,
            node,
            static_cast<uint8_t>(index >> 8),
            static_cast<uint8_t>(index),
            sub,
            static_cast<uint8_t>(start >> 8),
            static_cast<uint8_t>(start),
            static_cast<uint8_t>(count >> 8),
            static_cast<uint8_t>(count)};
  }
  // The data of an upload response after checking its header against the
  // request; `size` gets the object size.
  static bool upload_data(const Bytes& rsp, const Bytes& req, Bytes* data, uint32_t* size) {
    if (rsp.size() < 16u || !std::equal(req.begin(), req.begin() + 2, rsp.begin())) return false;
    if (!std::equal(req.begin() + 3, req.begin() + 10, rsp.begin() + 3)) return false;  // node..start
    const size_t count = static_cast<size_t>(rsp[10] << 8 | rsp[11]);
    if (rsp.size() != 16u + count) return false;
    *size = static_cast<uint32_t>(rsp[12]) << 24 | static_cast<uint32_t>(rsp[13]) << 16 |
            static_cast<uint32_t>(rsp[14]) << 8 | rsp[15];
    data->assign(rsp.begin() + 16, rsp.end());
    return true;
  }
  static Bytes nmt(uint8_t node, uint8_t command) {
    return {0x2B, 0x0D, 0x60, 0x00, node, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, command};
  }
  // Waits for node 2's heartbeat with state byte `state` (candump -L line).
  static bool heartbeat_seen(const char* state) {
    const std::string want = std::string(" 702#") + state;
    return candump_->wait_line([&](const std::string& l) { return l.find(want) != std::string::npos; },
                               kUmlDeadline);
  }

  static TempDir* dir_;
  static LineChild* candump_;
  static NodeProcess* node_[2];
  static ModbusMaster* master_;
};

TempDir* NodeNetwork::dir_ = nullptr;
LineChild* NodeNetwork::candump_ = nullptr;
NodeProcess* NodeNetwork::node_[2] = {nullptr, nullptr};
ModbusMaster* NodeNetwork::master_ = nullptr;

TEST_F(NodeNetwork, LibmodbusCannotReceiveA2BResponse) {
  send({0x2B, 0x0D, 0x80, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00});  // network view
  uint8_t rsp[MODBUS_RTU_MAX_ADU_LENGTH];
  EXPECT_EQ(modbus_receive_confirmation(master_->ctx(), rsp), -1)
      << "libmodbus parsed it: the tests could use modbus_receive_confirmation";
  usleep(100000);  // what libmodbus left of the response
  drain(master_->fd());
}

TEST_F(NodeNetwork, UploadFromTheSecondNodeEqualsTheGatewaysOwn) {
  Bytes remote, local;
  uint32_t size_remote = 0, size_local = 0;
  const Bytes req2 = upload(2, 0x1018, 2);
  ASSERT_TRUE(upload_data(transact(req2), req2, &remote, &size_remote));
  const Bytes req1 = upload(1, 0x1018, 2);
  ASSERT_TRUE(upload_data(transact(req1), req1, &local, &size_local));
  EXPECT_EQ(size_remote, 4u);
  EXPECT_EQ(remote, local) << "both nodes are mb2co-node: the same product code";
  EXPECT_TRUE(candump_->wait_line(
      [](const std::string& l) { return l.find(" 602#4018100200") != std::string::npos; }, kUmlDeadline))
      << "the SDO upload request went over the bus";
}

TEST_F(NodeNetwork, DownloadToTheSecondNode) {
  const Bytes req = {0x2B, 0x0D, 0x20, 0x00, 0x02, 0x10, 0x17, 0x00, 0x00,
                     0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0xC8, 0x00};  // 1017h = 200 ms
  const Bytes rsp = transact(req);
  ASSERT_EQ(rsp.size(), 16u);
  EXPECT_TRUE(std::equal(rsp.begin(), rsp.end(), req.begin())) << "the header and size echoed";
  Bytes value;
  uint32_t size = 0;
  const Bytes back = upload(2, 0x1017, 0);
  ASSERT_TRUE(upload_data(transact(back), back, &value, &size));
  EXPECT_EQ(value, (Bytes{0xC8, 0x00}));
  const Bytes restore = {0x2B, 0x0D, 0x20, 0x00, 0x02, 0x10, 0x17, 0x00, 0x00,
                         0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x64, 0x00};  // back to 100 ms
  EXPECT_EQ(transact(restore).size(), 16u);
}

TEST_F(NodeNetwork, SegmentedUploadOf1008InWindows) {
  Bytes whole, local;
  uint32_t size = 0, size_local = 0;
  const Bytes req = upload(2, 0x1008, 0);
  ASSERT_TRUE(upload_data(transact(req), req, &whole, &size));
  EXPECT_GT(size, 4u) << "longer than an expedited transfer";
  EXPECT_EQ(whole.size(), size);
  const Bytes own = upload(1, 0x1008, 0);
  ASSERT_TRUE(upload_data(transact(own), own, &local, &size_local));
  EXPECT_EQ(whole, local);
  EXPECT_TRUE(candump_->wait_line([](const std::string& l) { return l.find(" 602#60") != std::string::npos; },
                                  kUmlDeadline))
      << "segments were requested";
  // In windows of 4 bytes: more follows until the last one.
  Bytes joined;
  for (uint16_t start = 0; start < size; start = static_cast<uint16_t>(start + 4)) {
    const Bytes w = upload(2, 0x1008, 0, start, 4);
    const Bytes rsp = transact(w);
    Bytes part;
    uint32_t total = 0;
    ASSERT_TRUE(upload_data(rsp, w, &part, &total));
    EXPECT_EQ(total, size);
    EXPECT_EQ(rsp[2] & 0x01, start + 4u < size ? 1 : 0) << "more follows at " << start;
    joined.insert(joined.end(), part.begin(), part.end());
  }
  EXPECT_EQ(joined, whole);
}

TEST_F(NodeNetwork, NmtStopAndStartSeenInTheHeartbeat) {
  // candump's lines are taken in order: the NMT frame, then the heartbeat.
  ASSERT_EQ(transact(nmt(2, 0x02)), nmt(2, 0x02)) << "the request echoed";
  EXPECT_TRUE(candump_->wait_line(
      [](const std::string& l) { return l.find(" 000#0202") != std::string::npos; }, kUmlDeadline));
  EXPECT_TRUE(heartbeat_seen("04")) << "node 2 stopped";
  ASSERT_EQ(transact(nmt(2, 0x01)), nmt(2, 0x01));
  EXPECT_TRUE(candump_->wait_line(
      [](const std::string& l) { return l.find(" 000#0102") != std::string::npos; }, kUmlDeadline));
  EXPECT_TRUE(heartbeat_seen("05")) << "node 2 operational again";
}

TEST_F(NodeNetwork, MissingNodeAbortsWithTimeoutWithinTheDocumentedTime) {
  const auto sent = std::chrono::steady_clock::now();
  const Bytes rsp = transact(upload(9, 0x1000, 0), 5s);
  const auto elapsed = std::chrono::steady_clock::now() - sent;
  EXPECT_EQ(rsp, (Bytes{0xAB, 0x04, 0x0D, 0x05, 0x04, 0x00, 0x00}));
  // The abort went to the silent node as well (candump's lines are taken in
  // order: this one is not left for a later test).
  EXPECT_TRUE(candump_->wait_line(
      [](const std::string& l) { return l.find(" 609#8000100000000405") != std::string::npos; },
      kUmlDeadline));
  EXPECT_GE(elapsed, kSdoTimeout);
  EXPECT_LE(elapsed, kSdoTimeout + kSlack);
}

TEST_F(NodeNetwork, BadRequestsGetException03) {
  const Bytes bad[] = {
      {0x2B, 0x0D, 0x00, 0x01, 0x02, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00},        // reserved byte
      {0x2B, 0x0D, 0x00, 0x00, 0x02, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00},              // one byte short
      {0x2B, 0x0D, 0x00, 0x00, 0x00, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00},        // SDO to node 0
      {0x2B, 0x0D, 0x60, 0x00, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x03},  // no such NMT command
      {0x2B, 0x0D, 0xE0, 0x00, 0x02, 0x10, 0x18, 0x01, 0x00, 0x00, 0x00, 0x00},        // service 7
  };
  for (const Bytes& req : bad) EXPECT_EQ(transact(req), (Bytes{0xAB, 0x03}));
}

TEST_F(NodeNetwork, OwnRegistersAnsweredWhileARemoteTransferRuns) {
  drain(master_->fd());
  send(upload(9, 0x1000, 0));  // node 9 is silent: 500 ms of transfer
  usleep(20000);               // the RTU gap between two requests (more than t3.5)
  const auto asked = std::chrono::steady_clock::now();
  uint16_t regs[2] = {};
  EXPECT_EQ(modbus_read_input_registers(master_->ctx(), 0, 2, regs), 2);
  // Long before the transfer's 500 ms: not queued behind it.
  EXPECT_LT(std::chrono::steady_clock::now() - asked, 400ms) << "not queued behind the transfer";
  // Another 2Bh/0Dh meanwhile: busy.
  EXPECT_EQ(transact(upload(2, 0x1018, 2)), (Bytes{0xAB, 0x06}));
  // The master moved on: the transfer's answer is never sent. It would
  // leave in the same loop pass as the gateway's abort to node 9 (the
  // transfer's end), which candump shows.
  EXPECT_TRUE(candump_->wait_line(
      [](const std::string& l) { return l.find(" 609#8000100000000405") != std::string::npos; },
      kUmlDeadline));
  uint8_t late = 0;
  EXPECT_FALSE(read_exact(master_->fd(), &late, 1, 100ms)) << "a late answer came";
  // And the gateway serves again.
  Bytes value;
  uint32_t size = 0;
  const Bytes req = upload(2, 0x1018, 2);
  EXPECT_TRUE(upload_data(transact(req), req, &value, &size));
}

TEST_F(NodeNetwork, MultiPartDownloadToTheSecondNodesDomain) {
  // 1F50h/1 of mb2co-node (program data, a DOMAIN): 30 bytes in parts of 14,
  // 7 and 9, each starting where the previous ended (control 21h, then 20h);
  // a part before the last is whole 7-byte segments (11 bytes: exception 03).
  Bytes value(30);
  for (size_t i = 0; i < value.size(); ++i) value[i] = static_cast<uint8_t>(0xA0 + i);
  const Bytes eleven = {0x2B, 0x0D, 0x21, 0x00, 0x02, 0x1F, 0x50, 0x01,
                        0x00, 0x00, 0x00, 11,   0x00, 0x00, 0x00, 30};
  Bytes refused = eleven;
  refused.insert(refused.end(), value.begin(), value.begin() + 11);
  EXPECT_EQ(transact(refused), (Bytes{0xAB, 0x03})) << "11 bytes before the last part";
  const uint16_t parts[][2] = {{0, 14}, {14, 7}, {21, 9}};
  for (const auto& part : parts) {
    const bool last = part[0] + part[1] == 30;
    Bytes req = {0x2B,
                 0x0D,
                 static_cast<uint8_t>(last ? 0x20 : 0x21),
                 0x00,
                 0x02,
                 0x1F,
                 0x50,
                 0x01,
                 0x00,
                 static_cast<uint8_t>(part[0]),
                 0x00,
                 static_cast<uint8_t>(part[1]),
                 0x00,
                 0x00,
                 0x00,
                 30};
    req.insert(req.end(), value.begin() + part[0], value.begin() + part[0] + part[1]);
    const Bytes rsp = transact(req);
    ASSERT_EQ(rsp.size(), 16u) << "part at " << part[0];
    EXPECT_TRUE(std::equal(rsp.begin() + 3, rsp.end(), req.begin() + 3)) << "part at " << part[0];
  }
  Bytes back;
  uint32_t size = 0;
  const Bytes up = upload(2, 0x1F50, 1);
  ASSERT_TRUE(upload_data(transact(up), up, &back, &size));
  EXPECT_EQ(size, 30u);
  EXPECT_EQ(back, value);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
