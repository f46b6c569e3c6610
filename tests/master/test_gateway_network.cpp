// mb2co-master through a gateway (--via-modbus), without a serial line:
// GatewayNetwork against a scripted gateway that decodes each request with
// the shared codec's slave side (parse_net_request) and answers as
// docs/gateway-network.md says (windows, parts, exception 04 with the abort
// code, 06 busy, 01, silence). What the tests hold: the requests on the
// wire, the data that arrive, and that results read the same as over
// SocketCAN (failure text, exit codes).
#include <gtest/gtest.h>

#include <deque>
#include <map>
#include <memory>
#include <vector>

#include "crc/crc16.h"
#include "exit_codes.h"
#include "gateway_network.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "transfer_run.h"

namespace mb2co {
namespace master {
namespace {

using modbus::NetMessage;
using modbus::NetService;

const uint8_t kSlave = 7;

/// A gateway in the test's hands: an object store per node, answers
/// scripted ahead of time where a test wants something else.
class ScriptedGateway : public GatewayChannel {
 public:
  enum class Reply { kNormal, kSilence, kGarbage, kBusy, kException01, kException03 };
  /// (node, index, sub) → object bytes; absent: abort 06020000h.
  std::map<uint32_t, std::vector<uint8_t>> od;
  /// Nodes that do not answer: the gateway's client times out (05040000h).
  std::vector<uint8_t> silent;
  /// Replies for the next requests, in order; then kNormal.
  std::deque<Reply> script;
  /// Every request as decoded, its data copied (m.data points nowhere
  /// after the exchange).
  struct Seen {
    NetMessage m{};
    std::vector<uint8_t> data;
  };
  std::vector<Seen> seen;
  std::vector<uint32_t> timeouts_ms;

  static uint32_t key(uint8_t node, uint16_t index, uint8_t sub) {
    return (static_cast<uint32_t>(node) << 24) | (static_cast<uint32_t>(index) << 8) | sub;
  }

  Exchange exchange(const uint8_t* request, uint16_t length, uint32_t timeout_ms,
                    modbus::NetResponse* out) override {
    timeouts_ms.push_back(timeout_ms);
    EXPECT_TRUE(crc_ok(request, length));
    EXPECT_EQ(request[0], kSlave);
    Seen s;
    EXPECT_TRUE(modbus::parse_net_request(request + 1, static_cast<uint16_t>(length - 3), s.m))
        << "a request the gateway would answer with exception 03";
    s.data.assign(s.m.data, s.m.data + s.m.data_length);
    seen.push_back(s);
    const Reply reply = script.empty() ? Reply::kNormal : script.front();
    if (!script.empty()) script.pop_front();
    uint8_t* pdu = adu_ + 1;
    uint16_t n = 0;
    switch (reply) {
      case Reply::kSilence:
        return Exchange::failed(Outcome::kNoAnswer, "no answer (scripted)");
      case Reply::kGarbage:
        return Exchange::failed(Outcome::kBadAnswer, "garbage (scripted)");
      case Reply::kBusy:
        n = exception(pdu, 0x06);
        break;
      case Reply::kException01:
        n = exception(pdu, 0x01);
        break;
      case Reply::kException03:
        n = exception(pdu, 0x03);
        break;
      case Reply::kNormal:
        n = answer(s.m, pdu);
        break;
    }
    adu_[0] = request[0];
    const uint16_t total = append_crc(adu_, static_cast<uint16_t>(n + 1));
    const modbus::ParseStatus st = modbus::parse_net_response(request, length, adu_, total, *out);
    EXPECT_TRUE(st == modbus::ParseStatus::kOk || st == modbus::ParseStatus::kException)
        << "the scripted answer does not parse: " << static_cast<int>(st);
    return Exchange::answered();
  }
  std::string where() const override { return "slave 7 on the script"; }

  /// What the last download left in the store.
  const std::vector<uint8_t>& object(uint8_t node, uint16_t index, uint8_t sub) {
    return od[key(node, index, sub)];
  }

 private:
  static uint16_t exception(uint8_t* pdu, uint8_t code) {
    pdu[0] = 0xAB;
    pdu[1] = code;
    return 2;
  }

  uint16_t answer(const NetMessage& q, uint8_t* pdu) {
    NetMessage r = q;
    r.more_follows = false;
    if (q.service == NetService::kNmt) return modbus::build_net_response(pdu, 253, r);
    for (uint8_t id : silent)
      if (id == q.node_id) return modbus::build_net_abort(pdu, 0x05040000u);
    const uint32_t k = key(q.node_id, q.index, q.sub);
    if (q.service == NetService::kSdoUpload) {
      auto it = od.find(k);
      if (it == od.end()) return modbus::build_net_abort(pdu, 0x06020000u);
      const std::vector<uint8_t>& b = it->second;
      const size_t room = q.count ? q.count : modbus::net::kMaxSdoData;
      const size_t left = b.size() > q.start ? b.size() - q.start : 0;
      const uint16_t count = static_cast<uint16_t>(left < room ? left : room);
      r.count = count;
      r.object_size = static_cast<uint32_t>(b.size());
      r.more_follows = q.start + count < b.size();
      r.data = b.data() + q.start;
      r.data_length = count;
      return modbus::build_net_response(pdu, 253, r);
    }
    // Download: parts in order, the object replaced when the last arrives.
    if (k == key(5, 0x1000, 0)) return modbus::build_net_abort(pdu, 0x06010002u);  // read only
    if (q.start == 0) part_.clear();
    EXPECT_EQ(q.start, part_.size()) << "parts out of order";
    part_.insert(part_.end(), q.data, q.data + q.data_length);
    if (!q.more_follows) od[k] = part_;
    r.data_length = 0;
    return modbus::build_net_response(pdu, 253, r);
  }

  uint8_t adu_[modbus::kMaxAduBytes + 2];
  std::vector<uint8_t> part_;
};

std::unique_ptr<Transfer> upload(uint8_t node, uint16_t index, uint8_t sub) {
  std::unique_ptr<Transfer> t(new Transfer);
  t->node = node;
  t->index = index;
  t->sub = sub;
  return t;
}

std::vector<uint8_t> pattern(size_t n) {
  std::vector<uint8_t> b(n);
  for (size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(i * 7 + 3);
  return b;
}

TEST(GatewayNetwork, ShortUploadIsOneRequestNamingNodeIndexAndSub) {
  ScriptedGateway gw;
  gw.od[ScriptedGateway::key(4, 0x1018, 1)] = {0x2C, 0x0B, 0, 0};
  GatewayNetwork net(gw, kSlave, 3000);
  auto t = upload(4, 0x1018, 1);
  net.queue(t.get());
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(t->ok());
  EXPECT_EQ(t->data, (std::vector<uint8_t>{0x2C, 0x0B, 0, 0}));
  ASSERT_EQ(gw.seen.size(), 1u);
  EXPECT_EQ(gw.seen[0].m.service, NetService::kSdoUpload);
  EXPECT_EQ(gw.seen[0].m.node_id, 4);
  EXPECT_EQ(gw.seen[0].m.index, 0x1018);
  EXPECT_EQ(gw.seen[0].m.sub, 1);
  EXPECT_EQ(gw.seen[0].m.start, 0);
  EXPECT_EQ(gw.timeouts_ms[0], 3000u);
  EXPECT_EQ(net.pending(), 0u);
}

TEST(GatewayNetwork, LongUploadComesInWindowsAtGrowingStartingAddresses) {
  ScriptedGateway gw;
  const std::vector<uint8_t> name = pattern(600);  // 237 + 237 + 126
  gw.od[ScriptedGateway::key(4, 0x1008, 0)] = name;
  GatewayNetwork net(gw, kSlave, 3000);
  auto t = upload(4, 0x1008, 0);
  net.queue(t.get());
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(t->ok());
  EXPECT_EQ(t->data, name);
  ASSERT_EQ(gw.seen.size(), 3u);
  EXPECT_EQ(gw.seen[0].m.start, 0);
  EXPECT_EQ(gw.seen[1].m.start, modbus::net::kMaxSdoData);
  EXPECT_EQ(gw.seen[2].m.start, 2 * modbus::net::kMaxSdoData);
}

TEST(GatewayNetwork, AnUploadTakesAtMostMaxBytesAndStreamsThroughWrite) {
  ScriptedGateway gw;
  const std::vector<uint8_t> name = pattern(600);
  gw.od[ScriptedGateway::key(4, 0x1008, 0)] = name;
  GatewayNetwork net(gw, kSlave, 3000);
  // 600 bytes of at most 500: refused at the first window, which names the
  // size, as our own client refuses an indicated size (05040005h).
  auto t = upload(4, 0x1008, 0);
  t->max_bytes = 500;
  net.queue(t.get());
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_EQ(t->result, canopen::kAbortOutOfMemory);
  EXPECT_FALSE(t->by_server);
  EXPECT_EQ(gw.seen.size(), 1u);
  EXPECT_NE(t->failure().find("longer than 500 bytes"), std::string::npos) << t->failure();
  // Within the bound, every window goes to `write` as it comes, none to data.
  std::vector<uint8_t> written;
  auto u = upload(4, 0x1008, 0);
  u->max_bytes = 600;
  u->write = [&written](const uint8_t* bytes, size_t n) {
    written.insert(written.end(), bytes, bytes + n);
    return canopen::kSdoOk;
  };
  net.queue(u.get());
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(u->ok()) << u->failure();
  EXPECT_EQ(written, name);
  EXPECT_TRUE(u->data.empty());
  EXPECT_EQ(u->bytes, 600u);
}

TEST(GatewayNetwork, LongDownloadGoesInPartsWithMoreFollowsOnAllButTheLast) {
  ScriptedGateway gw;
  GatewayNetwork net(gw, kSlave, 3000);
  Transfer t;
  t.node = 4;
  t.index = 0x1F50;
  t.sub = 1;
  t.upload = false;
  t.data = pattern(500);
  net.queue(&t);
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(t.ok()) << t.failure();
  EXPECT_EQ(gw.object(4, 0x1F50, 1), t.data);
  ASSERT_EQ(gw.seen.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(gw.seen[i].m.service, NetService::kSdoDownload);
    EXPECT_EQ(gw.seen[i].m.object_size, 500u);
    EXPECT_EQ(gw.seen[i].m.more_follows, i < 2) << "part " << i;
  }
  EXPECT_EQ(gw.seen[0].data.size(), modbus::net::kMaxPartBytes) << "whole 7-byte segments: 231 bytes";
  EXPECT_EQ(gw.seen[1].m.start, modbus::net::kMaxPartBytes);
  EXPECT_EQ(gw.seen[2].data.size(), 500u - 2 * modbus::net::kMaxPartBytes);
}

TEST(GatewayNetwork, EmptyDownloadIsOneLastPart) {
  ScriptedGateway gw;
  GatewayNetwork net(gw, kSlave, 3000);
  Transfer t;
  t.node = 4;
  t.index = 0x2001;
  t.upload = false;
  net.queue(&t);
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(t.ok());
  ASSERT_EQ(gw.seen.size(), 1u);
  EXPECT_FALSE(gw.seen[0].m.more_follows);
  EXPECT_EQ(gw.seen[0].m.object_size, 0u);
}

TEST(GatewayNetwork, AbortCodesReadAsOverSocketCan) {
  ScriptedGateway gw;
  gw.silent = {9};
  GatewayNetwork net(gw, kSlave, 3000);
  auto missing_object = upload(4, 0x2FFF, 0);
  auto missing_node = upload(9, 0x1000, 0);
  Transfer read_only;
  read_only.node = 5;
  read_only.index = 0x1000;
  read_only.upload = false;
  read_only.data = {1, 2, 3, 4};
  net.queue(missing_object.get());
  net.queue(missing_node.get());
  net.queue(&read_only);
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(net.link_status());

  EXPECT_EQ(missing_object->result, canopen::kAbortNoObject);
  EXPECT_TRUE(missing_object->by_server);
  EXPECT_EQ(missing_object->failure(),
            "node 4 2FFFh/0: SDO abort 06020000h (object does not exist in the object dictionary)");
  EXPECT_EQ(exit_code_of(*missing_object), kExitRefused);

  // The gateway's client timed out: silence of the node, exit 4, as when
  // our own client times out.
  EXPECT_EQ(missing_node->result, canopen::kAbortTimeout);
  EXPECT_FALSE(missing_node->by_server);
  EXPECT_EQ(missing_node->failure(), "node 9 1000h/0: SDO abort sent 05040000h (SDO protocol timed out)");
  EXPECT_EQ(exit_code_of(*missing_node), kExitNoAnswer);

  EXPECT_EQ(read_only.result, canopen::kAbortReadOnly);
  EXPECT_EQ(read_only.failure(), "node 5 1000h/0: SDO abort 06010002h (attempt to write a read only object)");
}

TEST(GatewayNetwork, BusyGatewayIsAskedAgain) {
  ScriptedGateway gw;
  gw.od[ScriptedGateway::key(4, 0x1017, 0)] = {0xE8, 0x03};
  gw.script = {ScriptedGateway::Reply::kBusy, ScriptedGateway::Reply::kBusy};
  GatewayNetwork net(gw, kSlave, 3000);
  auto t = upload(4, 0x1017, 0);
  net.queue(t.get());
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_TRUE(t->ok());
  EXPECT_EQ(gw.seen.size(), 3u);
}

TEST(GatewayNetwork, SilentGatewayEndsEveryTransferAtOnceWithExit3) {
  ScriptedGateway gw;
  gw.script = {ScriptedGateway::Reply::kSilence};
  GatewayNetwork net(gw, kSlave, 3000);
  std::vector<std::unique_ptr<Transfer>> ts;
  for (uint8_t node = 1; node <= 5; ++node) {
    ts.push_back(upload(node, 0x1000, 0));
    net.queue(ts.back().get());
  }
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_EQ(gw.seen.size(), 1u) << "no further request waits out the same silence";
  EXPECT_FALSE(net.link_status());
  EXPECT_EQ(net.link_status().message(), "no answer (scripted)");
  for (auto& t : ts) {
    EXPECT_TRUE(t->finished);
    EXPECT_TRUE(t->link_down);
    EXPECT_EQ(exit_code_of(*t), kExitBus);
  }
  // Queued after the link went down: ends at once too.
  auto late = upload(3, 0x1000, 0);
  net.queue(late.get());
  EXPECT_TRUE(late->finished);
  EXPECT_EQ(net.pending(), 0u);
}

/// 1000h of nodes 3 and 4 through `gw`, the first request answered with
/// `first_reply`; returns the network's link status.
Status probe_two(ScriptedGateway& gw, ScriptedGateway::Reply first_reply, std::unique_ptr<Transfer>* a,
                 std::unique_ptr<Transfer>* b) {
  gw.script = {first_reply};
  GatewayNetwork net(gw, kSlave, 3000);
  *a = upload(3, 0x1000, 0);
  *b = upload(4, 0x1000, 0);
  net.queue(a->get());
  net.queue(b->get());
  EXPECT_TRUE(net.run(nullptr));
  EXPECT_EQ(net.pending(), 0u);
  return net.link_status();
}

TEST(GatewayNetwork, ExceptionOneMeansNoNetworkAccessAndEndsEverything) {
  ScriptedGateway gw;
  std::unique_ptr<Transfer> a, b;
  const Status link = probe_two(gw, ScriptedGateway::Reply::kException01, &a, &b);
  EXPECT_FALSE(link);
  EXPECT_NE(link.message().find("exception 01h"), std::string::npos);
  EXPECT_TRUE(b->link_down);
  EXPECT_EQ(gw.seen.size(), 1u);
}

TEST(GatewayNetwork, ExceptionThreeRefusesOnlyThatTransfer) {
  ScriptedGateway gw;
  gw.od[ScriptedGateway::key(4, 0x1000, 0)] = {0x91, 0x01, 0x0F, 0x00};
  std::unique_ptr<Transfer> a, b;
  EXPECT_TRUE(probe_two(gw, ScriptedGateway::Reply::kException03, &a, &b));
  EXPECT_EQ(exit_code_of(*a), kExitRefused);
  EXPECT_NE(a->failure().find("node 3 1000h/0: the gateway answered exception 03h"), std::string::npos)
      << a->failure();
  EXPECT_TRUE(b->ok());
}

TEST(GatewayNetwork, NodesTakeTurnsAndOnDoneMayQueueMore) {
  // scan's pattern: a probe's on_done queues the node's identity reads.
  ScriptedGateway gw;
  for (uint8_t node : std::vector<uint8_t>{2, 3}) {
    gw.od[ScriptedGateway::key(node, 0x1000, 0)] = {0, 0, 0, 0};
    gw.od[ScriptedGateway::key(node, 0x1018, 1)] = {node, 0, 0, 0};
  }
  GatewayNetwork net(gw, kSlave, 3000);
  std::vector<std::unique_ptr<Transfer>> more;
  std::vector<std::unique_ptr<Transfer>> probes;
  for (uint8_t node : std::vector<uint8_t>{2, 3}) {
    probes.push_back(upload(node, 0x1000, 0));
    probes.back()->on_done = [&](Transfer& t) {
      more.push_back(upload(t.node, 0x1018, 1));
      net.queue(more.back().get());
    };
    net.queue(probes.back().get());
  }
  ASSERT_TRUE(net.run(nullptr));
  ASSERT_EQ(more.size(), 2u);
  for (auto& t : more) {
    EXPECT_TRUE(t->ok());
    EXPECT_EQ(t->data[0], t->node);
  }
  ASSERT_EQ(gw.seen.size(), 4u);
  EXPECT_EQ(gw.seen[0].m.node_id, 2);
  EXPECT_EQ(gw.seen[1].m.node_id, 3);
  EXPECT_EQ(gw.seen[2].m.node_id, 2);
  EXPECT_EQ(gw.seen[3].m.node_id, 3);
}

TEST(GatewayNetwork, AbortAllFromOnDoneEndsTheRestWithoutRequests) {
  // dump's pattern: silence at the first upload drops everything queued.
  ScriptedGateway gw;
  gw.silent = {6};
  GatewayNetwork net(gw, kSlave, 3000);
  std::vector<std::unique_ptr<Transfer>> ts;
  for (uint8_t sub = 0; sub < 5; ++sub) {
    ts.push_back(upload(6, 0x1018, sub));
    ts.back()->on_done = [&](Transfer& t) {
      if (!t.ok() && !t.by_server) net.abort_all(canopen::kAbortTimeout);
    };
    net.queue(ts.back().get());
  }
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_EQ(gw.seen.size(), 1u);
  EXPECT_EQ(net.pending(), 0u);
  for (auto& t : ts) EXPECT_EQ(t->result, canopen::kAbortTimeout);
}

TEST(GatewayNetwork, DropQueuedLeavesOtherNodesAlone) {
  ScriptedGateway gw;
  gw.od[ScriptedGateway::key(3, 0x1000, 0)] = {1, 2, 3, 4};
  GatewayNetwork net(gw, kSlave, 3000);
  auto a = upload(2, 0x1000, 0);
  auto b = upload(3, 0x1000, 0);
  net.queue(a.get());
  net.queue(b.get());
  net.drop_queued(2, canopen::kAbortTimeout);
  EXPECT_EQ(net.pending(), 1u);
  ASSERT_TRUE(net.run(nullptr));
  EXPECT_EQ(a->result, canopen::kAbortTimeout);
  EXPECT_TRUE(b->ok());
  EXPECT_EQ(gw.seen.size(), 1u);
}

TEST(GatewayNetwork, NmtGoesAsOneConfirmedRequest) {
  ScriptedGateway gw;
  EXPECT_TRUE(gateway_nmt(gw, kSlave, 3000, canopen::kNmtStop, 4));
  EXPECT_TRUE(gateway_nmt(gw, kSlave, 3000, canopen::kNmtStart, 0));
  ASSERT_EQ(gw.seen.size(), 2u);
  EXPECT_EQ(gw.seen[0].m.service, NetService::kNmt);
  EXPECT_EQ(gw.seen[0].m.node_id, 4);
  EXPECT_EQ(gw.seen[0].data, std::vector<uint8_t>{canopen::kNmtStop});
  EXPECT_EQ(gw.seen[1].m.node_id, 0);
  EXPECT_EQ(gw.seen[1].data, std::vector<uint8_t>{canopen::kNmtStart});
  gw.script = {ScriptedGateway::Reply::kSilence};
  const Status silent = gateway_nmt(gw, kSlave, 3000, canopen::kNmtStart, 4);
  EXPECT_FALSE(silent);
  EXPECT_EQ(silent.message(), "no answer (scripted)");
}

}  // namespace
}  // namespace master
}  // namespace mb2co
