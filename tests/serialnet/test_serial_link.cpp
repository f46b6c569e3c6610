// The adapter on its own, driven by hand: what it queues and refuses, the
// priority order and the window it keeps, the SDO bytes it leaves off and
// pads back, and the exact times of token passes and the starter's recovery.
#include <gtest/gtest.h>
#include <string.h>

#include <vector>

#include "serialnet/serial_link.h"

namespace mb2co {
namespace serialnet {
namespace {

struct Written {
  uint32_t at_us;
  std::vector<uint8_t> bytes;
};

// A line that records what the link writes, stamped with the test's clock.
struct Line {
  uint32_t now = 0;
  std::vector<Written> out;
  bool refuse = false;
  modbus::ByteSink sink() { return modbus::ByteSink{&Line::write, this}; }
  static bool write(void* ctx, const uint8_t* d, uint16_t n) {
    Line& l = *static_cast<Line*>(ctx);
    if (l.refuse) return false;
    l.out.push_back(Written{l.now, std::vector<uint8_t>(d, d + n)});
    return true;
  }
};

struct Got {
  std::vector<CanFrame> frames;
  std::vector<uint32_t> at;
  CanReceiver receiver() {
    return CanReceiver{[](void* ctx, const CanFrame& f, uint32_t now_us) {
                         static_cast<Got*>(ctx)->frames.push_back(f);
                         static_cast<Got*>(ctx)->at.push_back(now_us);
                       },
                       this};
  }
};

BusConfig config7(Access access, uint32_t window_us = 2000, uint32_t guard_us = 100) {
  BusConfig c = {};
  c.set = connection_set(IdBits::k7);
  c.baud = 115200;  // 87 µs a byte
  c.access = access;
  c.first_node = 1;
  c.last_node = 3;
  c.window_us = window_us;
  c.guard_us = guard_us;
  return c;
}

CanFrame frame(uint32_t id, std::initializer_list<uint8_t> data) {
  CanFrame f = {};
  f.id = id;
  for (uint8_t b : data) f.data[f.dlc++] = b;
  return f;
}

// Decodes what the link wrote: one message per write.
SerialMessage decode(const ConnectionSet& set, const Written& w) {
  Decoder d(set);
  for (uint8_t b : w.bytes) {
    if (d.push(b, 0) == Decoder::kMessage) return d.message();
  }
  ADD_FAILURE() << "no message in a write";
  return SerialMessage{};
}

// Hands `link` a message as if from the line, its last byte at `end_us`.
void hear(SerialLink& link, const SerialMessage& m, uint32_t end_us) {
  uint8_t buf[kMaxEncodedBytes];
  const uint8_t n = encode(link.config().set, m, buf, sizeof buf);
  for (uint8_t i = 0; i < n; ++i) link.on_byte(buf[i], end_us - (n - 1u - i) * 87u);
}

SerialMessage sync_naming(uint8_t node) {
  SerialMessage m = {};
  m.id = 1u << 4;  // code 1, node 0 in the 7-bit set
  m.length = 1;
  m.data[0] = node;
  return m;
}

// Runs process() from `from` to `to` in steps of `step` µs.
void run(SerialLink& link, Line& line, uint32_t from, uint32_t to, uint32_t step = 1) {
  for (line.now = from; static_cast<int32_t>(to - line.now) >= 0; line.now += step) link.process(line.now);
}

TEST(SerialLink, SendsOnlyInItsWindowHighestPriorityFirstAndWhatFitsWaits) {
  Line line;
  SerialLink link(config7(Access::kPolled, 2000, 100), 2, line.sink());
  // Queued before any window: heartbeat, SDO response, TPDO1, EMCY.
  ASSERT_TRUE(link.send(frame(0x702, {0x05})));
  ASSERT_TRUE(link.send(frame(0x582, {0x60, 0x00, 0x20, 0x01})));
  ASSERT_TRUE(link.send(frame(0x182, {1, 2})));
  ASSERT_TRUE(link.send(frame(0x082, {0x00, 0x81, 0x11, 0, 0, 0, 0, 0})));
  EXPECT_EQ(link.queued(), 4);
  run(link, line, 0, 10000, 10);
  EXPECT_TRUE(line.out.empty()) << "no window yet";
  hear(link, sync_naming(3), 10500);  // somebody else's window
  run(link, line, 10500, 13000, 10);
  EXPECT_TRUE(line.out.empty());

  hear(link, sync_naming(2), 20000);
  EXPECT_TRUE(link.in_window());
  run(link, line, 20000, 23000);
  // EMCY (13 bytes = 1131 µs) then TPDO1 (7 bytes = 609 µs) end by
  // 20000 + 2000 - 100; the SDO response (8 bytes) would not: it waits.
  ASSERT_EQ(line.out.size(), 2u);
  EXPECT_EQ(decode(link.config().set, line.out[0]).id, (1u << 4) | 2u);  // EMCY: code 1, node 2
  EXPECT_EQ(line.out[0].at_us, 20000u);
  EXPECT_EQ(decode(link.config().set, line.out[1]).id, (2u << 4) | 2u);  // TPDO1: code 2
  EXPECT_EQ(line.out[1].at_us, 20000u + link.line_time_us(static_cast<uint8_t>(line.out[0].bytes.size())));
  EXPECT_EQ(link.queued(), 2);
  EXPECT_FALSE(link.in_window());

  hear(link, sync_naming(2), 40000);
  run(link, line, 40000, 43000);
  ASSERT_EQ(line.out.size(), 4u);
  EXPECT_EQ(decode(link.config().set, line.out[2]).id, (7u << 4) | 2u);  // transmit SDO: code 7
  EXPECT_EQ(decode(link.config().set, line.out[3]).id, (0u << 4) | 2u);  // heartbeat: code 0
  EXPECT_EQ(link.queued(), 0);
  EXPECT_EQ(link.counters().windows, 2);
}

TEST(SerialLink, EqualIdsKeepTheirOrder) {
  Line line;
  SerialLink link(config7(Access::kPolled, 10000), 1, line.sink());
  for (uint8_t k = 0; k < 5; ++k)
    ASSERT_TRUE(link.send(frame(0x581, {static_cast<uint8_t>(0x00 | k), 1, 2})));
  ASSERT_TRUE(link.send(frame(0x181, {9})));
  hear(link, sync_naming(1), 100);
  run(link, line, 100, 10000);
  ASSERT_EQ(line.out.size(), 6u);
  EXPECT_EQ(decode(link.config().set, line.out[0]).data[0], 9);
  for (uint8_t k = 0; k < 5; ++k) EXPECT_EQ(decode(link.config().set, line.out[k + 1u]).data[0], k);
}

TEST(SerialLink, AWaitingPdoIsReplacedByTheNewestOneOthersQueue) {
  Line line;
  SerialLink link(config7(Access::kPolled, 10000), 1, line.sink());
  ASSERT_TRUE(link.send(frame(0x181, {1})));
  ASSERT_TRUE(link.send(frame(0x081, {0x10, 0x81, 0x11, 0, 0, 0, 0, 0})));
  ASSERT_TRUE(link.send(frame(0x181, {2})));                                // newer data of the same TPDO
  ASSERT_TRUE(link.send(frame(0x081, {0x00, 0x00, 0x00, 0, 0, 0, 0, 0})));  // EMCY: an event each
  ASSERT_TRUE(link.send(frame(0x201, {7})));
  EXPECT_EQ(link.queued(), 4);
  hear(link, sync_naming(1), 100);
  run(link, line, 100, 10000);
  ASSERT_EQ(line.out.size(), 4u);
  EXPECT_EQ(decode(link.config().set, line.out[0]).data[0], 0x10);
  EXPECT_EQ(decode(link.config().set, line.out[1]).data[0], 0x00);
  EXPECT_EQ(decode(link.config().set, line.out[2]).id, (2u << 4) | 1u);
  EXPECT_EQ(decode(link.config().set, line.out[2]).data[0], 2) << "only the newest TPDO1";
  EXPECT_EQ(decode(link.config().set, line.out[3]).id, (3u << 4) | 1u);
}

TEST(SerialLink, FullQueueRefusesAndCountsAndUnmappableFramesAreDropped) {
  Line line;
  SerialLink link(config7(Access::kPolled), 1, line.sink());
  for (uint8_t k = 0; k < TxQueue::kCapacity; ++k) ASSERT_TRUE(link.send(frame(0x581, {0x00, k})));
  EXPECT_FALSE(link.send(frame(0x081, {})));
  EXPECT_EQ(link.counters().overflow, 1);
  // No serial form: TPDO3, a node id beyond 15, extended, remote.
  Line line2;
  SerialLink other(config7(Access::kPolled), 1, line2.sink());
  CanFrame ext = frame(0x181, {1});
  ext.flags = CanFrame::kExtended;
  CanFrame rtr = frame(0x181, {});
  rtr.flags = CanFrame::kRtr;
  EXPECT_TRUE(other.send(frame(0x381, {1})));
  EXPECT_TRUE(other.send(frame(0x190, {1})));
  EXPECT_TRUE(other.send(ext));
  EXPECT_TRUE(other.send(rtr));
  EXPECT_EQ(other.counters().unmappable_tx, 4);
  EXPECT_EQ(other.queued(), 0);
}

TEST(SerialLink, SdoTrailingZerosLeaveTheLineAndComeBackAsEightBytes) {
  Line line;
  SerialLink tx(config7(Access::kPolled), 5, line.sink());
  const CanFrame sdo = frame(0x585, {0x43, 0x18, 0x10, 0x01, 0x2A, 0x00, 0x00, 0x00});
  const CanFrame pdo = frame(0x185, {0x00, 0x00});  // PDO zeros are data: kept
  ASSERT_TRUE(tx.send(sdo));
  ASSERT_TRUE(tx.send(pdo));
  hear(tx, sync_naming(5), 100);
  run(tx, line, 100, 3000);
  ASSERT_EQ(line.out.size(), 2u);
  EXPECT_EQ(decode(tx.config().set, line.out[0]).length, 2);
  EXPECT_EQ(decode(tx.config().set, line.out[1]).length, 5);

  Line quiet;
  SerialLink rx(config7(Access::kPolled), 1, quiet.sink());
  Got got;
  rx.set_receiver(got.receiver());
  uint32_t t = 5000;
  for (const Written& w : line.out) {
    for (uint8_t b : w.bytes) rx.on_byte(b, t += 87);
  }
  ASSERT_EQ(got.frames.size(), 2u);
  EXPECT_EQ(got.frames[0].id, 0x185u);
  EXPECT_EQ(got.frames[0].dlc, 2);
  EXPECT_EQ(got.frames[1].id, 0x585u);
  EXPECT_EQ(got.frames[1].dlc, 8);
  EXPECT_EQ(memcmp(got.frames[1].data, sdo.data, 8), 0);
  EXPECT_EQ(got.at[1], t) << "stamped with its last byte";
  EXPECT_EQ(rx.counters().received, 2);
}

TEST(SerialLink, ReservedIdsFromTheLineAreDroppedAndCounted) {
  Line line;
  SerialLink rx(config7(Access::kPolled), 1, line.sink());
  Got got;
  rx.set_receiver(got.receiver());
  SerialMessage m = {};
  m.id = 3u << 4;  // code 3 with node id 0: reserved
  hear(rx, m, 1000);
  EXPECT_TRUE(got.frames.empty());
  EXPECT_EQ(rx.counters().unmappable_rx, 1);
}

TEST(SerialLink, NextDeadlineSaysWhenToTalk) {
  Line line;
  SerialLink link(config7(Access::kPolled, 2000, 100), 2, line.sink());
  uint32_t at = 0;
  NextDeadline idle(50);
  link.next_deadline(idle);
  EXPECT_FALSE(idle.result(&at)) << "a polled node waits for its SYNC: an input";
  ASSERT_TRUE(link.send(frame(0x182, {1})));
  hear(link, sync_naming(2), 1000);
  NextDeadline open(1000);
  link.next_deadline(open);
  ASSERT_TRUE(open.result(&at));
  EXPECT_EQ(at, 1000u);
  line.now = 1000;
  link.process(1000);
  NextDeadline busy(1000);
  link.next_deadline(busy);
  ASSERT_TRUE(busy.result(&at));
  EXPECT_EQ(at, 1000u + 6u * 87u) << "the end of our message (6 bytes)";

  Line pline;
  SerialLink poller(config7(Access::kPoller, 2000, 100), 0, pline.sink());
  NextDeadline first(0);
  poller.next_deadline(first);
  ASSERT_TRUE(first.result(&at));
  EXPECT_EQ(at, 0u);
  poller.process(0);  // SYNC(1), 6 bytes
  ASSERT_EQ(pline.out.size(), 1u);
  poller.process(6 * 87);
  NextDeadline next(6 * 87);
  poller.next_deadline(next);
  ASSERT_TRUE(next.result(&at));
  EXPECT_EQ(at, 6u * 87u + 2000u) << "the next poll when the window ends";
}

TEST(SerialLink, PollerPollsEveryNodeOneWindowEach) {
  Line line;
  SerialLink poller(config7(Access::kPoller, 2000, 100), 0, line.sink());
  Got got;
  poller.set_receiver(got.receiver());
  run(poller, line, 0, 20000);
  ASSERT_GE(line.out.size(), 7u);
  const uint32_t sync_us = poller.line_time_us(static_cast<uint8_t>(line.out[0].bytes.size()));
  for (size_t k = 0; k < 7; ++k) {
    const SerialMessage m = decode(poller.config().set, line.out[k]);
    EXPECT_EQ(m.id, 1u << 4);
    EXPECT_EQ(m.data[0], 1 + k % 3) << "counters 1, 2, 3, 1, ...";
    EXPECT_EQ(line.out[k].at_us, k * (sync_us + 2000u));
  }
  // Its own node sees each SYNC too, when it has left.
  ASSERT_GE(got.frames.size(), 7u);
  EXPECT_EQ(got.frames[0].id, 0x080u);
  EXPECT_EQ(got.at[0], sync_us);
}

TEST(SerialLink, TokenHolderPassesAtOnceWhenIdleAndAtItsWindowEndWhenBusy) {
  Line line;
  SerialLink link(config7(Access::kToken, 3000, 100), 3, line.sink());
  hear(link, sync_naming(3), 1000);
  EXPECT_TRUE(link.holds_token());
  line.now = 1000;
  link.process(1000);
  ASSERT_EQ(line.out.size(), 1u);
  EXPECT_EQ(decode(link.config().set, line.out[0]).data[0], 1) << "after the last node, the first";
  EXPECT_FALSE(link.holds_token());

  // Busy: 8 SDO segments of 8 bytes (13 on the line, 1131 µs): one ends
  // before W - G - T_sync (3000 - 100 - 11 * 87 µs), a second would not;
  // then the pass, ending inside the window. 7 wait for the next token.
  for (uint8_t k = 0; k < 8; ++k) ASSERT_TRUE(link.send(frame(0x583, {k, 1, 2, 3, 4, 5, 6, 7})));
  hear(link, sync_naming(3), 10000);
  run(link, line, 10000, 14000);
  ASSERT_EQ(line.out.size(), 3u);
  EXPECT_EQ(line.out[1].at_us, 10000u);
  const Written& pass = line.out[2];
  EXPECT_EQ(pass.at_us, 10000u + 13u * 87u);
  EXPECT_EQ(decode(link.config().set, pass).id, 1u << 4);
  EXPECT_LE(pass.at_us + link.line_time_us(static_cast<uint8_t>(pass.bytes.size())), 10000u + 3000u);
  EXPECT_EQ(link.queued(), 7);
}

TEST(SerialLink, StarterStartsTheTokenAndRecoversItAfterWindowPlusGuard) {
  Line line;
  SerialLink starter(config7(Access::kTokenStarter, 3000, 100), 1, line.sink());
  line.now = 0;
  starter.process(0);
  ASSERT_EQ(line.out.size(), 1u);
  EXPECT_EQ(decode(starter.config().set, line.out[0]).data[0], 1) << "the first node: itself";
  const uint32_t t1 = starter.line_time_us(static_cast<uint8_t>(line.out[0].bytes.size()));
  run(starter, line, 1, t1);
  ASSERT_EQ(line.out.size(), 2u) << "idle: passed to node 2 at once";
  EXPECT_EQ(line.out[1].at_us, t1);
  EXPECT_EQ(decode(starter.config().set, line.out[1]).data[0], 2);
  const uint32_t t2 = t1 + starter.line_time_us(static_cast<uint8_t>(line.out[1].bytes.size()));
  // Node 2 is silent: at t2 + W + G the starter names node 3.
  run(starter, line, t1 + 1, t2 + 3100 - 1);
  EXPECT_EQ(line.out.size(), 2u);
  run(starter, line, t2 + 3100, t2 + 3100);
  ASSERT_EQ(line.out.size(), 3u);
  EXPECT_EQ(decode(starter.config().set, line.out[2]).data[0], 3);
  EXPECT_EQ(starter.counters().token_recoveries, 1);
  EXPECT_LE(t2 + 3100 + starter.line_time_us(static_cast<uint8_t>(line.out[2].bytes.size())) - t2,
            starter.token_recovery_bound_us());
  // Node 3 answers (a message, then its pass): no recovery.
  SerialMessage hb = {};
  hb.id = 3;  // heartbeat of node 3
  hb.length = 1;
  hb.data[0] = 0x05;
  const uint32_t t3 = t2 + 3100 + 600;
  hear(starter, hb, t3 + 1000);
  run(starter, line, t3, t3 + 1000 + 3100 - 1, 10);
  EXPECT_EQ(line.out.size(), 3u) << "activity restarts the watch";
  hear(starter, sync_naming(1), t3 + 2000);
  EXPECT_TRUE(starter.holds_token());
  EXPECT_EQ(starter.counters().token_recoveries, 1);
}

TEST(SerialLink, ConfigsThatCannotWorkAreNamed) {
  BusConfig c = config7(Access::kPolled, 2500, 100);
  EXPECT_EQ(check_config(c), ConfigError::kOk);
  c.last_node = 16;  // the 7-bit set has 15
  EXPECT_EQ(check_config(c), ConfigError::kNodeRange);
  c.last_node = 3;
  c.first_node = 0;
  EXPECT_EQ(check_config(c), ConfigError::kNodeRange);
  c.first_node = 4;
  EXPECT_EQ(check_config(c), ConfigError::kNodeRange);
  c.first_node = 1;
  c.baud = 0;
  EXPECT_EQ(check_config(c), ConfigError::kBaud);
  c.baud = 115200;
  // The longest message (27 bytes, 2349 µs) must fit in W - G, and in token
  // passing the pass (11 bytes, 957 µs) too.
  c.window_us = 100 + 27 * 87;
  EXPECT_EQ(check_config(c), ConfigError::kOk);
  c.window_us -= 1;
  EXPECT_EQ(check_config(c), ConfigError::kWindowTooShort);
  c.access = Access::kToken;
  c.window_us = 100 + 27 * 87 + 11 * 87;
  EXPECT_EQ(check_config(c), ConfigError::kOk);
  c.window_us -= 1;
  EXPECT_EQ(check_config(c), ConfigError::kWindowTooShort);
  // Per-node windows: each must hold it; the longest sets the bound.
  const uint32_t windows[3] = {5000, 9000, 100 + 38 * 87 - 1};
  c.node_windows_us = windows;
  EXPECT_EQ(check_config(c), ConfigError::kWindowTooShort);
  EXPECT_EQ(window_of(c, 2), 9000u);
  EXPECT_EQ(window_of(c, 7), c.window_us) << "outside first..last";
  EXPECT_EQ(longest_window(c), 9000u);
  const uint32_t ok[3] = {5000, 9000, 100 + 38 * 87};
  c.node_windows_us = ok;
  EXPECT_EQ(check_config(c), ConfigError::kOk);
  Line line;
  SerialLink link(c, 1, line.sink());
  EXPECT_EQ(link.token_recovery_bound_us(), 9000u + 100u + 11u * 87u);
}

TEST(SerialLink, ARefusedWriteIsCountedAndRetried) {
  Line line;
  SerialLink link(config7(Access::kPolled), 1, line.sink());
  ASSERT_TRUE(link.send(frame(0x181, {1})));
  hear(link, sync_naming(1), 100);
  line.refuse = true;
  line.now = 100;
  link.process(100);
  EXPECT_EQ(link.counters().line_refused, 1);
  EXPECT_EQ(link.queued(), 1);
  line.refuse = false;
  line.now = 200;
  link.process(200);
  EXPECT_EQ(line.out.size(), 1u);
  EXPECT_EQ(link.queued(), 0);
}

}  // namespace
}  // namespace serialnet
}  // namespace mb2co
