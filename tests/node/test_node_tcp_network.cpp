// FC 2Bh / MEI 0Dh over Modbus/TCP (docs/mb2co-node.md "Modbus/TCP"; ctest
// runs this binary inside hil/uml/run-with-vcan.sh): node 1 serves
// --tcp beside its pty, node 2 is only on vcan0. A libmodbus TCP program
// sends the raw requests of docs/gateway-network.md (libmodbus 3.1.6 cannot
// receive a 2Bh response: read off its socket here) and reaches node 2; a
// remote transfer is answered when done while other TCP clients and the
// line are served; another 2Bh/0Dh meanwhile gets 06; a client that goes
// away mid transfer disturbs nobody. Responses are checked byte by byte.
#include <gtest/gtest.h>
#include <modbus.h>

#include <algorithm>
#include <chrono>
#include <string>

#include "node_harness.h"
#include "tcp_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kUmlDeadline = 60s;  // bounds a failure only
// The gateway's SDO client gives a silent node this long (docs/gateway-network.md).
constexpr auto kSdoTimeout = 500ms;

// docs/gateway-network.md, "SDO upload": node, index, sub, whole object.
TcpBytes upload(uint8_t node, uint16_t index, uint8_t sub) {
  return {0x2B, 0x0D, 0x00, 0x00, node, static_cast<uint8_t>(index >> 8), static_cast<uint8_t>(index),
          sub,  0x00, 0x00, 0x00, 0x00};
}
// "SDO download" of a 2-byte value (expedited at the node).
TcpBytes download_u16(uint8_t node, uint16_t index, uint8_t sub, uint16_t value) {
  return {0x2B,
          0x0D,
          0x20,
          0x00,
          node,
          static_cast<uint8_t>(index >> 8),
          static_cast<uint8_t>(index),
          sub,
          0x00,
          0x00,
          0x00,
          0x02,
          0x00,
          0x00,
          0x00,
          0x02,
          static_cast<uint8_t>(value),
          static_cast<uint8_t>(value >> 8)};
}
TcpBytes nmt(uint8_t node, uint8_t command) {
  return {0x2B, 0x0D, 0x60, 0x00, node, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, command};
}
// The data of an upload answer to `req`, after checking its echoed header.
bool upload_data(const TcpBytes& rsp, const TcpBytes& req, TcpBytes* data) {
  if (rsp.size() < 16u || !std::equal(req.begin(), req.begin() + 2, rsp.begin())) return false;
  if (!std::equal(req.begin() + 3, req.begin() + 10, rsp.begin() + 3)) return false;
  const size_t count = static_cast<size_t>(rsp[10] << 8 | rsp[11]);
  if (rsp.size() != 16u + count) return false;
  data->assign(rsp.begin() + 16, rsp.end());
  return true;
}
const TcpBytes kReadDebounce = {0x03, 0x00, 0x07, 0x00, 0x01};  // HR 7: 20 ms
const TcpBytes kDebounce20 = {0x03, 0x02, 0x00, 0x14};

class NodeTcpNetwork : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    candump_ = new LineChild;
    const Status listening = start_candump_listening(*candump_, kUmlDeadline);
    if (!listening) failure_ = listening.message();
    for (int i = 0; i < 2 && failure_.empty(); ++i) {
      const std::string id = std::to_string(i + 1);
      std::vector<std::string> args{"--can", "vcan0", "--node-id", id, "--pty", dir_->path(id + ".pty")};
      if (i == 0) args.insert(args.end(), {"--tcp", "127.0.0.1:0"});
      node_[i] = new NodeProcess;
      if (!node_[i]->start(args, kUmlDeadline)) failure_ = "node " + id + ": " + node_[i]->error();
    }
  }
  static void TearDownTestSuite() {
    for (NodeProcess*& n : node_) {
      delete n;
      n = nullptr;
    }
    delete candump_;
    delete dir_;
  }
  void SetUp() override { ASSERT_TRUE(failure_.empty()) << failure_; }
  static const std::string& address() { return node_[0]->tcp_address(); }
  static bool candump_saw(const std::string& text) {
    return candump_->wait_line([&](const std::string& l) { return l.find(text) != std::string::npos; },
                               kUmlDeadline);
  }

  static TempDir* dir_;
  static LineChild* candump_;
  static NodeProcess* node_[2];
  static std::string failure_;
};

TempDir* NodeTcpNetwork::dir_ = nullptr;
LineChild* NodeTcpNetwork::candump_ = nullptr;
NodeProcess* NodeTcpNetwork::node_[2] = {nullptr, nullptr};
std::string NodeTcpNetwork::failure_;

TEST_F(NodeTcpNetwork, LibmodbusTcpRawRequestsReachTheSecondNode) {
  const size_t colon = address().rfind(':');
  modbus_t* ctx = modbus_new_tcp(address().substr(0, colon).c_str(), std::stoi(address().substr(colon + 1)));
  ASSERT_NE(ctx, nullptr);
  ASSERT_EQ(modbus_connect(ctx), 0) << modbus_strerror(errno);
  // Unit id 255 first (libmodbus adds the MBAP header, transaction 0 for a
  // raw request in 3.1.6); the answer is read off its socket.
  auto transact = [&](const TcpBytes& pdu) {
    TcpBytes raw{0xFF};
    raw.insert(raw.end(), pdu.begin(), pdu.end());
    if (modbus_send_raw_request(ctx, raw.data(), static_cast<int>(raw.size())) <= 0) return TcpBytes{};
    const TcpBytes f = TcpPeer::read_frame(modbus_get_socket(ctx));
    if (f.size() < 8 || f[2] != 0 || f[3] != 0 || f[6] != 0xFF) return TcpBytes{};
    return TcpBytes(f.begin() + 7, f.end());
  };
  TcpBytes remote, local;
  const TcpBytes req2 = upload(2, 0x1018, 2);
  ASSERT_TRUE(upload_data(transact(req2), req2, &remote));
  const TcpBytes req1 = upload(1, 0x1018, 2);
  ASSERT_TRUE(upload_data(transact(req1), req1, &local));
  EXPECT_EQ(remote.size(), 4u);
  EXPECT_EQ(remote, local) << "both nodes are mb2co-node: the same product code";
  EXPECT_TRUE(candump_saw(" 602#4018100200")) << "the SDO upload request went over the bus";

  // A download (1017h = 200 ms), read back, restored.
  const TcpBytes down = download_u16(2, 0x1017, 0, 200);
  EXPECT_EQ(transact(down), TcpBytes(down.begin(), down.begin() + 16)) << "header and size echoed";
  TcpBytes value;
  const TcpBytes back = upload(2, 0x1017, 0);
  ASSERT_TRUE(upload_data(transact(back), back, &value));
  EXPECT_EQ(value, (TcpBytes{0xC8, 0x00}));
  EXPECT_EQ(transact(download_u16(2, 0x1017, 0, 100)).size(), 16u);

  // A segmented upload (1008h, the device name) equals the gateway's own.
  TcpBytes name2, name1;
  const TcpBytes n2 = upload(2, 0x1008, 0), n1 = upload(1, 0x1008, 0);
  ASSERT_TRUE(upload_data(transact(n2), n2, &name2));
  ASSERT_TRUE(upload_data(transact(n1), n1, &name1));
  EXPECT_GT(name2.size(), 4u) << "longer than an expedited transfer";
  EXPECT_EQ(name2, name1);

  // NMT stop and start of node 2, seen in its heartbeat.
  EXPECT_EQ(transact(nmt(2, 0x02)), nmt(2, 0x02)) << "the request echoed";
  EXPECT_TRUE(candump_saw(" 000#0202"));
  EXPECT_TRUE(candump_saw(" 702#04")) << "node 2 stopped";
  EXPECT_EQ(transact(nmt(2, 0x01)), nmt(2, 0x01));
  EXPECT_TRUE(candump_saw(" 702#05")) << "node 2 operational again";
  modbus_close(ctx);
  modbus_free(ctx);
}

TEST_F(NodeTcpNetwork, ARemoteTransferIsAnsweredWhenDoneWhileOthersAreServed) {
  TcpPeer slow, other, third;
  ASSERT_TRUE(slow.connect(address()));
  ASSERT_TRUE(other.connect(address()));
  ASSERT_TRUE(third.connect(address()));
  ModbusMaster line;
  ASSERT_TRUE(line.open(node_[0]->device(), 2s)) << line.error();
  const auto sent = std::chrono::steady_clock::now();
  ASSERT_TRUE(slow.send(mbap(0x5101, 0x01, upload(9, 0x1000, 0))));  // node 9 is silent: 500 ms
  // Meanwhile: another client's registers, the line's, and another 2Bh/0Dh
  // (busy: one remote transfer at a time). Each before the slow answer.
  int served = 0;
  for (uint16_t t = 1; t <= 3; ++t) {
    EXPECT_EQ(other.ask(t, 0xFF, kReadDebounce), kDebounce20);
    ++served;
  }
  EXPECT_EQ(line.holding_register(7), 20) << "the line is served too";
  EXPECT_EQ(third.ask(0x7777, 0xFF, upload(2, 0x1018, 2)), (TcpBytes{0xAB, 0x06})) << "busy";
  EXPECT_TRUE(slow.silent_for(0ms)) << "the slow answer is not there yet: the others did not wait for it";
  EXPECT_EQ(served, 3);
  // Then the transfer's own answer, on its connection, with its transaction id.
  const TcpBytes answer = slow.frame(kUmlDeadline);
  const auto elapsed = std::chrono::steady_clock::now() - sent;
  EXPECT_EQ(answer, mbap(0x5101, 0x01, {0xAB, 0x04, 0x0D, 0x05, 0x04, 0x00, 0x00})) << "abort 05040000h";
  EXPECT_GE(elapsed, kSdoTimeout);
  EXPECT_TRUE(candump_saw(" 609#8000100000000405"));
  EXPECT_TRUE(other.silent_for(50ms) && third.silent_for(0ms)) << "nobody else got it";
  // And the service is free again.
  TcpBytes value;
  const TcpBytes req = upload(2, 0x1018, 2);
  EXPECT_TRUE(upload_data(third.ask(0x7778, 0xFF, req), req, &value));
}

// The node's count of requests it answered none (CPT5, `counters?` noresp).
unsigned no_responses(NodeProcess& node) {
  const std::string v = field_of(node.ask("counters?", "counters "), "noresp");
  return v.empty() ? ~0u : static_cast<unsigned>(std::stoul(v));
}

TEST_F(NodeTcpNetwork, AClientGoneMidTransferDisturbsNobody) {
  const unsigned unanswered = no_responses(*node_[0]);
  TcpBytes value;
  const TcpBytes req = upload(2, 0x1018, 2);
  {
    TcpPeer gone;
    ASSERT_TRUE(gone.connect(address()));
    ASSERT_TRUE(gone.send(mbap(1, 0xFF, upload(9, 0x1000, 0))));
    // Closed with its answer outstanding (when the node has read the request:
    // another client's answer shows the pass that read it is over).
    TcpPeer witness;
    ASSERT_TRUE(witness.connect(address()));
    EXPECT_EQ(witness.ask(1, 0xFF, kReadDebounce), kDebounce20);
  }
  TcpPeer next;
  ASSERT_TRUE(next.connect(address()));
  EXPECT_EQ(next.ask(2, 0xFF, kReadDebounce), kDebounce20);
  // The abandoned transfer runs to its timeout; after it the service serves.
  EXPECT_TRUE(candump_saw(" 609#8000100000000405"));
  EXPECT_TRUE(upload_data(next.ask(3, 0xFF, req), req, &value));
  EXPECT_EQ(value.size(), 4u);
  EXPECT_EQ(no_responses(*node_[0]), unanswered + 1) << "the dropped answer, counted once (CPT5)";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
