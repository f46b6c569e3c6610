// The slave's side of FC 2Bh / MEI 0Dh: the handler answers now or later,
// a later answer is dropped once the master sends anything else, and the
// diagnostic counters count each request once.
#include <gtest/gtest.h>

#include "modbus/network_pdu.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

// A handler that answers what `reply` says: 0 defers, else that many bytes
// of `pdu` (copied over the request).
struct FakeService {
  uint16_t reply = 0;
  uint8_t pdu[16] = {};
  int calls = 0;
  static uint16_t handle(void* ctx, uint8_t* p, uint16_t, uint16_t capacity) {
    FakeService& s = *static_cast<FakeService*>(ctx);
    ++s.calls;
    if (s.reply == 0u || s.reply > capacity) return 0;
    for (uint16_t i = 0; i < s.reply; ++i) p[i] = s.pdu[i];
    return s.reply;
  }
  NetRequestHandler handler{&FakeService::handle, this};
};

Bytes view_request() {
  Bytes adu(32);
  adu.resize(build_net_view(adu.data(), 32, kSlaveAddress, 0));
  return adu;
}

TEST(NetworkSlave, WithoutAHandlerTheFunctionIsUnknown) {
  SlaveHarness h;
  EXPECT_EQ(h.transact(view_request()), with_crc({kSlaveAddress, 0xAB, 0x01}));
}

TEST(NetworkSlave, ADeferredAnswerIsSentLaterAndCountedOnce) {
  SlaveHarness h;
  FakeService s;
  h.slave.set_net_handler(&s.handler);
  EXPECT_TRUE(h.transact(view_request()).empty()) << "deferred";
  EXPECT_EQ(s.calls, 1);
  ASSERT_TRUE(h.slave.answer_pending());
  const uint8_t echo[3] = {0x2B, 0x0D, 0x80};
  for (int i = 0; i < 3; ++i) h.slave.response_pdu()[i] = echo[i];
  ASSERT_TRUE(h.slave.send_deferred(3));
  EXPECT_EQ(h.responses.back(), with_crc({kSlaveAddress, 0x2B, 0x0D, 0x80}));
  EXPECT_FALSE(h.slave.answer_pending());
  EXPECT_FALSE(h.slave.send_deferred(3)) << "one answer per request";
  EXPECT_EQ(h.slave.counters().server_messages, 1u);
  EXPECT_EQ(h.slave.counters().no_responses, 0u);
}

TEST(NetworkSlave, AnythingTheMasterSendsDropsThePendingAnswer) {
  SlaveHarness h;
  FakeService s;
  h.slave.set_net_handler(&s.handler);
  EXPECT_TRUE(h.transact(view_request()).empty());
  ASSERT_TRUE(h.slave.answer_pending());
  // An FC 03 to the slave's own registers: answered at once.
  const Bytes regs = h.transact(read_holding(0, 1));
  ASSERT_FALSE(regs.empty());
  EXPECT_EQ(regs[1], 0x03);
  EXPECT_FALSE(h.slave.answer_pending()) << "the master gave the answer up";
  const size_t sent = h.responses.size();
  EXPECT_FALSE(h.slave.send_deferred(3));
  EXPECT_EQ(h.responses.size(), sent) << "nothing sent late";
  EXPECT_EQ(h.slave.counters().no_responses, 1u) << "the dropped answer";
  // Even one stray character (a frame for another slave, noise) drops it.
  EXPECT_TRUE(h.transact(view_request()).empty());
  h.feed(read_holding(0, 1, 7), h.timing.t35_us);
  EXPECT_FALSE(h.slave.answer_pending());
}

TEST(NetworkSlave, TheAbortExceptionIsSentWholeAndCountedAsAnException) {
  SlaveHarness h;
  FakeService s;
  s.reply = build_net_abort(s.pdu, 0x06020000u);
  h.slave.set_net_handler(&s.handler);
  EXPECT_EQ(h.transact(view_request()), with_crc({kSlaveAddress, 0xAB, 0x04, 0x0D, 0x06, 0x02, 0x00, 0x00}));
  EXPECT_EQ(h.slave.counters().exceptions, 1u);
  // A plain exception from the handler takes the usual path, counted once.
  s.pdu[0] = 0xAB;
  s.pdu[1] = 0x06;
  s.reply = 2;
  EXPECT_EQ(h.transact(view_request()), with_crc({kSlaveAddress, 0xAB, 0x06}));
  EXPECT_EQ(h.slave.counters().exceptions, 2u);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
