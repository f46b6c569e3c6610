// SlaveCore's second way in (SlaveCore::serve, modbus/tcp_channel.h): a PDU
// from another framer is served by the same function codes and answered
// through its channel without address or CRC; FC 08 and listen-only mode
// stay the serial line's; an FC 2Bh/0Dh answer deferred for one channel
// survives requests of other channels and of the line, and goes to its own
// channel. Black box through the slave's public API.
#include <gtest/gtest.h>

#include "modbus/network_pdu.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

// A Modbus/TCP connection as the slave sees it: a PDU buffer and what it sent.
struct Client {
  uint8_t pdu[kMaxPduBytes] = {};
  std::vector<Bytes> sent;
  bool accepts = true;
  PduChannel channel{pdu, &Client::send, this};

  static bool send(void* ctx, const uint8_t* p, uint16_t n) {
    Client& c = *static_cast<Client*>(ctx);
    if (!c.accepts) return false;
    c.sent.emplace_back(p, p + n);
    return true;
  }
  // Serves `request` (a PDU); the answer it got at once, or {}.
  Bytes ask(SlaveCore& slave, const Bytes& request) {
    std::copy(request.begin(), request.end(), pdu);
    const size_t before = sent.size();
    slave.serve(channel, static_cast<uint16_t>(request.size()));
    return sent.size() > before ? sent.back() : Bytes{};
  }
};

// A FC 2Bh/0Dh service that defers every answer.
struct DeferringService {
  static uint16_t handle(void*, uint8_t*, uint16_t, uint16_t) { return 0; }
  NetRequestHandler handler{&DeferringService::handle, nullptr};
};

const Bytes kReadHolding = {0x03, 0x00, 0x00, 0x00, 0x02};             // HR 0..1
const Bytes kNetView = {0x2B, 0x0D, 0x80, 0, 0, 0, 0, 0, 0, 0, 0, 0};  // network view from node 0

TEST(TcpSlave, ServesThePduAndAnswersItWithoutAddressOrCrc) {
  SlaveHarness h;
  h.bank.holding_registers[0] = 0x1234;
  h.bank.holding_registers[1] = 0x5678;
  Client c;
  EXPECT_EQ(c.ask(h.slave, kReadHolding), (Bytes{0x03, 0x04, 0x12, 0x34, 0x56, 0x78}));
  EXPECT_EQ(c.ask(h.slave, {0x06, 0x00, 0x05, 0x00, 0x2A}), (Bytes{0x06, 0x00, 0x05, 0x00, 0x2A}));
  EXPECT_EQ(h.bank.holding_registers[5], 0x2Au);
  EXPECT_EQ(c.ask(h.slave, {0x03, 0xFF, 0x00, 0x00, 0x01}), (Bytes{0x83, 0x02})) << "the usual exceptions";
  EXPECT_TRUE(h.responses.empty()) << "nothing on the line";
  EXPECT_EQ(h.slave.counters().server_messages, 3u) << "counted: the line application's watchdog sees it";
  EXPECT_EQ(h.slave.counters().exceptions, 1u);
}

TEST(TcpSlave, DiagnosticsAndListenOnlyStayTheLines) {
  SlaveHarness h;
  Client c;
  EXPECT_EQ(c.ask(h.slave, {0x08, 0x00, 0x00, 0xA5, 0x5A}), (Bytes{0x88, 0x01})) << "FC 08: serial line only";
  // 08/04 on the line: the line listens only; a TCP client is still served.
  uint8_t adu[16];
  const uint16_t n = build_diagnostics(adu, sizeof adu, kSlaveAddress, 0x0004, 0x0000);
  EXPECT_TRUE(h.transact(Bytes(adu, adu + n)).empty());
  ASSERT_TRUE(h.slave.listen_only());
  EXPECT_EQ(c.ask(h.slave, kReadHolding).size(), 6u);
  EXPECT_TRUE(h.transact(read_holding(0, 2)).empty()) << "the line still listens only";
}

TEST(TcpSlave, ADeferredAnswerWaitsForItsChannelWhileOthersAreServed) {
  SlaveHarness h;
  DeferringService service;
  h.slave.set_net_handler(&service.handler);
  Client a, b;
  EXPECT_TRUE(a.ask(h.slave, kNetView).empty()) << "deferred";
  ASSERT_TRUE(h.slave.answer_pending());
  EXPECT_EQ(b.ask(h.slave, kReadHolding).size(), 6u) << "another client is served meanwhile";
  EXPECT_FALSE(h.transact(read_holding(0, 2)).empty()) << "and the line";
  ASSERT_TRUE(h.slave.answer_pending()) << "neither gave the answer up";
  EXPECT_EQ(h.slave.response_pdu(), a.pdu) << "the answer is built in its channel's buffer";
  const uint8_t view[3] = {0x2B, 0x0D, 0x80};
  std::copy(view, view + 3, h.slave.response_pdu());
  const size_t line_answers = h.responses.size();
  ASSERT_TRUE(h.slave.send_deferred(3));
  ASSERT_EQ(a.sent.size(), 1u);
  EXPECT_EQ(a.sent[0], Bytes(view, view + 3));
  EXPECT_EQ(b.sent.size(), 1u);
  EXPECT_EQ(h.responses.size(), line_answers) << "not on the line";
  EXPECT_EQ(h.slave.counters().no_responses, 0u);
}

TEST(TcpSlave, ALineAnswerDeferredSurvivesAClientsRequest) {
  SlaveHarness h;
  DeferringService service;
  h.slave.set_net_handler(&service.handler);
  uint8_t adu[32];
  const uint16_t n = build_net_view(adu, sizeof adu, kSlaveAddress, 0);
  EXPECT_TRUE(h.transact(Bytes(adu, adu + n)).empty());
  Client c;
  EXPECT_EQ(c.ask(h.slave, kReadHolding).size(), 6u);
  ASSERT_TRUE(h.slave.answer_pending());
  h.slave.response_pdu()[0] = 0x2B;
  ASSERT_TRUE(h.slave.send_deferred(1));
  EXPECT_EQ(h.responses.back(), with_crc({kSlaveAddress, 0x2B})) << "on the line, framed for it";
  EXPECT_EQ(c.sent.size(), 1u);
}

TEST(TcpSlave, TheClientsNextRequestOrItsGoingDropsItsDeferredAnswer) {
  SlaveHarness h;
  DeferringService service;
  h.slave.set_net_handler(&service.handler);
  Client a;
  EXPECT_TRUE(a.ask(h.slave, kNetView).empty());
  EXPECT_EQ(a.ask(h.slave, kReadHolding).size(), 6u);
  EXPECT_FALSE(h.slave.answer_pending()) << "its client moved on";
  EXPECT_EQ(h.slave.counters().no_responses, 1u);

  EXPECT_TRUE(a.ask(h.slave, kNetView).empty());
  Client b;
  h.slave.forget(b.channel);
  EXPECT_TRUE(h.slave.answer_pending()) << "another channel's going changes nothing";
  h.slave.forget(a.channel);
  EXPECT_FALSE(h.slave.answer_pending());
  EXPECT_FALSE(h.slave.send_deferred(3)) << "nothing sent to a closed connection";
  EXPECT_EQ(h.slave.counters().no_responses, 2u);
  EXPECT_EQ(h.transact(read_holding(0, 2)).size(), 9u) << "the line is served from its own buffer again";
}

TEST(TcpSlave, ARefusedSendIsCountedLikeTheLines) {
  SlaveHarness h;
  Client c;
  c.accepts = false;
  EXPECT_TRUE(c.ask(h.slave, kReadHolding).empty());
  EXPECT_EQ(h.slave.stats().send_failures, 1u);
  EXPECT_EQ(h.slave.counters().no_responses, 1u);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
