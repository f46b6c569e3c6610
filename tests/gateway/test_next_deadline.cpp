// Gateway::next_deadline (issue 10 item 3), black box: a gateway driven only
// at the deadlines it names, checking at every step that process() one
// microsecond earlier changes nothing (no frame, no serial byte, no OD value,
// the same LEDs, the same deadline). Each line-application timer (debounce,
// Modbus watchdog from power-on, blink of an unknown neighbour) and the
// self-start fire at exactly their time; a timer missing from next_deadline
// makes its test fail (the event comes late, or never).
#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "canopen/clock.h"
#include "gateway/gateway.h"

namespace mb2co {
namespace test {
namespace {

using gateway::Gateway;

/// A gateway that sleeps from deadline to deadline (as the line simulator).
class GatewayDeadline : public ::testing::Test {
 protected:
  static bool on_frame(void* ctx, const CanFrame&) {
    ++static_cast<GatewayDeadline*>(ctx)->frames;
    return true;
  }
  static bool on_serial(void* ctx, const uint8_t*, uint16_t) {
    ++static_cast<GatewayDeadline*>(ctx)->responses;
    return true;
  }

  void SetUp() override {
    gw.start(now, 1);
    leds = gw.process(now, buttons);
  }

  uint32_t get(uint16_t index, uint8_t sub) { return gw.od().get(gw.od().find(index, sub)); }
  void set(uint16_t index, uint8_t sub, uint32_t value) { gw.od().set(gw.od().find(index, sub), value); }
  /// Every OD value but 1013h's: the network clock (TIME) reads the time of
  /// the read, so it runs on between any two passes by definition; that is
  /// no change a deadline has to announce.
  std::vector<std::vector<uint8_t>> snapshot() const {
    std::vector<std::vector<uint8_t>> rows;
    Gateway& g = const_cast<Gateway&>(gw);
    const uint16_t clock_row = g.od().find(0x1013, 0);
    for (uint16_t r = 0; r < g.od().row_count(); ++r) {
      if (r == clock_row) continue;
      uint8_t buf[64];
      const uint16_t n = g.od().copy_out(r, buf, sizeof buf);
      rows.emplace_back(buf, buf + n);
    }
    return rows;
  }
  uint32_t deadline() {
    uint32_t at = 0;
    EXPECT_TRUE(gw.next_deadline(now, &at)) << "nothing pending at " << now;
    return at;
  }

  /// One step: process() at the deadline - 1 (must change nothing), then at
  /// the deadline (or at once when it is now).
  void step() {
    const uint32_t at = deadline();
    if (at != now) {
      const auto od_before = snapshot();
      const int frames_before = frames;
      const int responses_before = responses;
      now = at - 1;
      EXPECT_EQ(gw.process(now, buttons), leds) << "LEDs changed before the deadline " << at;
      EXPECT_EQ(frames, frames_before) << "a frame before the deadline " << at;
      EXPECT_EQ(responses, responses_before);
      EXPECT_TRUE(snapshot() == od_before) << "the OD changed before the deadline " << at;
      EXPECT_EQ(deadline(), at) << "the deadline moved";
      now = at;
    }
    leds = gw.process(now, buttons);
  }
  /// Steps until `done` holds (at most `max_steps`); returns the time it did.
  uint32_t step_until(const std::function<bool()>& done, int max_steps = 1000) {
    for (int i = 0; i < max_steps && !done(); ++i) step();
    EXPECT_TRUE(done()) << "never happened";
    return now;
  }

  int frames = 0;
  int responses = 0;
  uint32_t now = 0;
  uint8_t buttons = 0;
  uint8_t leds = 0;
  Gateway gw{gateway::GatewayPorts{CanSink{&on_frame, this}, modbus::ByteSink{&on_serial, this}, nullptr,
                                   115200, nullptr}};
};

TEST_F(GatewayDeadline, SelfStartAndTheNmtStateItShowsAreDueAtOnce) {
  // The first pass started the node (2000h/8): operational, but 2002h still
  // shows what the line application saw before, so the next pass is due now.
  EXPECT_EQ(gw.node().nmt_state(), canopen::kNmtOperational);
  EXPECT_EQ(get(0x2002, 0), canopen::kNmtPreOperational);
  EXPECT_EQ(deadline(), now);
  step();
  EXPECT_EQ(get(0x2002, 0), canopen::kNmtOperational);
  // A reset communication from the bus: the self-start after it is due now.
  CanFrame reset = {};
  reset.dlc = 2;
  reset.data[0] = canopen::kNmtResetCommunication;
  reset.data[1] = 1;
  now += 1000;
  gw.on_can_frame(reset, now);
  EXPECT_EQ(gw.node().nmt_state(), canopen::kNmtPreOperational);
  EXPECT_EQ(deadline(), now);
  step();
  EXPECT_EQ(gw.node().nmt_state(), canopen::kNmtOperational);
}

TEST_F(GatewayDeadline, ModbusWatchdogRunsFromPowerOn) {
  const uint32_t fired = step_until([&] { return get(0x2100, 4) == gateway::kCausePcSilent; });
  EXPECT_EQ(fired, 2000u * 1000u + 1u) << "2000h/9 = 2000 ms, then the first microsecond beyond";
}

TEST_F(GatewayDeadline, ButtonDebounce) {
  step_until([&] { return get(0x2002, 0) == canopen::kNmtOperational; });
  now += 5000;
  buttons = gateway::kStop;  // an input: the next pass samples it
  leds = gw.process(now, buttons);
  const uint32_t pressed = now;
  const uint32_t counted = step_until([&] { return get(0x2100, 6) == 1u; });
  EXPECT_EQ(counted, pressed + 20000u) << "2000h/6 = 20 ms";
  EXPECT_EQ(get(0x2300, 1), pressed) << "the edge is stamped when the contact moved";
}

TEST_F(GatewayDeadline, UnknownNeighbourBlinks) {
  set(0x2000, 9, 0);  // no watchdog stop in the way
  // Never heard since the reset: no heartbeat, no TPDO1 (flag 80h).
  ASSERT_EQ(get(0x2110, 3), gateway::kNeighbourUnknown | gateway::kNeighbourNotHeard);
  std::vector<uint32_t> changes;
  uint8_t before = leds & gateway::kLedRunPrev;
  step_until([&] {
    if ((leds & gateway::kLedRunPrev) != before) {
      before = leds & gateway::kLedRunPrev;
      changes.push_back(now);
    }
    return changes.size() == 4;
  });
  EXPECT_EQ(changes, (std::vector<uint32_t>{250000, 500000, 750000, 1000000}));
}

TEST_F(GatewayDeadline, ALostNeighbourIsShownByTheNextPass) {
  // Node 1 of a ring of 4 watches nodes 4 and 2 (1016h, 3 x 1017h).
  set(0x2000, 9, 0);
  const uint32_t consumer_ms = get(0x1016, 1) & 0xFFFFu;
  ASSERT_NE(consumer_ms, 0u);
  CanFrame hb = {};
  hb.id = 0x702;
  hb.dlc = 1;
  hb.data[0] = canopen::kNmtOperational;
  now += 1000;
  gw.on_can_frame(hb, now);
  const uint32_t heard = now;
  step();
  // Alive by its heartbeat; no TPDO1 of it yet (flag 80h stays).
  ASSERT_EQ(get(0x2120, 3), gateway::kNeighbourAlive | gateway::kNeighbourNotHeard);
  // The consumer time runs out inside the node's process() (the status is
  // written by its callback, after the line application ran in that pass).
  step_until([&] { return get(0x2120, 3) == (gateway::kNeighbourUnknown | gateway::kNeighbourNotHeard); });
  EXPECT_EQ(now, heard + consumer_ms * 1000u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
