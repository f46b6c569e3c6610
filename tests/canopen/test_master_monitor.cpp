// The master's node monitor (canopen/master/node_monitor.h) against real
// nodes of the node core on a virtual bus (heartbeat producer, node guarding
// answers, boot-up after an NMT reset) and against seed 004's frame trace:
// lost exactly when the consumer or life time runs out, back at the boot-up,
// state changes, toggle errors, and nothing from nodes that are not armed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "canopen/frame_out.h"
#include "canopen/master/nmt_master.h"
#include "canopen/master/node_monitor.h"
#include "test_master_bus.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Strings = std::vector<std::string>;

/// Records monitor events as "3 state 7F->05" with the time they came.
struct EventLog {
  explicit EventLog(const uint32_t* clock_us) : clock(clock_us) {}
  MonitorListener listener() { return MonitorListener{&EventLog::on, this}; }
  Strings take() {
    Strings out = events;
    events.clear();
    return out;
  }
  static void on(void* ctx, uint8_t id, MonitorEvent e, uint8_t old_state, uint8_t new_state) {
    EventLog& log = *static_cast<EventLog*>(ctx);
    static const char* const kNames[] = {"?", "lost", "back", "state", "boot-up", "toggle"};
    char buf[48];
    std::snprintf(buf, sizeof buf, "%u %s %02X->%02X", id, kNames[e], old_state, new_state);
    log.events.push_back(buf);
    log.times.push_back(*log.clock);
  }
  const uint32_t* clock;
  Strings events;
  std::vector<uint32_t> times;
};

/// A master with a monitor table on the bus.
class MasterMonitor : public ::testing::Test {
 protected:
  void SetUp() override {
    table.set_listener(events.listener());
    bus.master_process = [this](uint32_t t) { table.process(t, bus.master_sink()); };
    bus.master_rx = [this](const CanFrame& f, uint32_t t) { table.on_frame(f, t); };
  }
  /// The master's SDO request to node 3 (bytes as in seed 004 §2.11), acked.
  void sdo_to_node3(std::initializer_list<uint8_t> req) {
    const std::vector<uint8_t> b(req);
    const size_t before = bus.trace.size();
    ASSERT_TRUE(send_frame(sink, 0x603, 8, b.data()));
    bus.deliver();
    ASSERT_EQ(bus.trace.size(), before + 2);
    EXPECT_EQ(bus.trace.back().second.substr(0, 8), "<583> 60") << "write acknowledged";
  }
  /// Runs the bus to 100 µs before `at_us`, where nothing may be raised,
  /// then to `at_us`, where exactly `event` must come.
  void expect_exactly_at(uint32_t at_us, const std::string& event) {
    bus.run(at_us - 100u - bus.now);
    EXPECT_TRUE(events.take().empty()) << "nothing before " << at_us;
    bus.step(100);
    EXPECT_EQ(events.take(), Strings({event}));
    EXPECT_EQ(events.times.back(), at_us);
  }
  uint32_t deadline() {
    NextDeadline d(bus.now);
    table.next_deadline(d);
    uint32_t at = 0;
    EXPECT_TRUE(d.result(&at));
    return at;
  }

  MasterBus bus;
  CanSink sink = bus.master_sink();
  EventLog events{&bus.now};
  NodeMonitorTable<8> table;
  NmtMaster nmt{bus.master_sink()};
};

TEST_F(MasterMonitor, HeartbeatOfARealNodeLostExactlyAfterTheConsumerTimeAndBackOnItsBootUp) {
  ASSERT_TRUE(table.monitor(3)->watch_heartbeat(3, 500, 750));
  MasterBus::Station& node = bus.add_node(3);
  EXPECT_EQ(bus.take(), Strings({"<703> 00"}));
  EXPECT_EQ(events.take(), Strings({"3 boot-up FF->00"}));
  EXPECT_EQ(table.find(3)->link(), kLinkWaiting);

  // Seed 004: the master sets 1017h = 500 ms; the node's first heartbeat arms the monitor.
  sdo_to_node3({0x22, 0x17, 0x10, 0x00, 0xF4, 0x01, 0x00, 0x00});
  bus.run(600000);  // the producer restarts at the node's next process(): 500.1 ms
  EXPECT_EQ(bus.take(),
            Strings({"<603> 22 17 10 00 F4 01 00 00", "<583> 60 17 10 00 00 00 00 00", "<703> 7F"}));
  EXPECT_EQ(events.take(), Strings({"3 state 00->7F"}));
  EXPECT_EQ(table.find(3)->link(), kLinkAlive);

  ASSERT_TRUE(nmt.start(3));
  bus.deliver();
  bus.run(500000);
  EXPECT_EQ(bus.take(), Strings({"<000> 01 03", "<183> 00 00", "<703> 05"}));
  EXPECT_EQ(events.take(), Strings({"3 state 7F->05"}));

  // Heartbeats every 500 ms keep it alive for a while.
  bus.run(3000000);
  EXPECT_EQ(bus.take(), Strings(6, "<703> 05"));
  EXPECT_TRUE(events.take().empty());
  uint32_t last_hb = 0;
  ASSERT_TRUE(bus.last_time_of("<703> 05", &last_hb));
  EXPECT_EQ(deadline(), last_hb + 750000u);

  // The node falls off the bus: lost 750 ms after its last heartbeat, not before.
  node.plugged = false;
  expect_exactly_at(last_hb + 750000u, "3 lost 05->05");
  EXPECT_EQ(table.find(3)->link(), kLinkLost);
  EXPECT_EQ(table.lost_count(), 1u);
  bus.run(2000000);
  EXPECT_TRUE(events.take().empty()) << "lost is told once";

  // Back on the bus, reset by the master: its boot-up is the node coming back.
  node.plugged = true;
  ASSERT_TRUE(nmt.reset_node(3));
  bus.step(100);
  EXPECT_EQ(bus.take(), Strings({"<000> 81 03", "<703> 00"}));
  EXPECT_EQ(events.take(), Strings({"3 back 00->00", "3 boot-up 05->00"}));
  EXPECT_EQ(table.find(3)->link(), kLinkWaiting);
  EXPECT_EQ(table.lost_count(), 0u);
  // After the reset 1017h is 0 again: no heartbeats, and a monitor that is
  // not armed raises nothing.
  bus.run(5000000, 1000);
  EXPECT_TRUE(bus.take().empty());
  EXPECT_TRUE(events.take().empty());
}

TEST(MasterMonitorTrace, Seed004HeartbeatsGiveBootUpAndStateChanges) {
  uint32_t now = 0;
  EventLog events(&now);
  const MonitorListener l = events.listener();
  NodeMonitor m;
  ASSERT_TRUE(m.watch_heartbeat(3, 500, 750));
  EXPECT_TRUE(m.on_frame(F(0x703, {0x00}), now, l));
  now = 10000;
  EXPECT_TRUE(m.on_frame(F(0x703, {0x7F}), now, l));
  now = 510000;
  EXPECT_TRUE(m.on_frame(F(0x703, {0x05}), now, l));
  EXPECT_FALSE(m.on_frame(F(0x704, {0x05}), now, l)) << "another node's heartbeat";
  EXPECT_FALSE(m.on_frame(F(0x703, {0x05, 0x00}), now, l)) << "2 bytes: not a heartbeat";
  EXPECT_EQ(events.take(), Strings({"3 boot-up FF->00", "3 state 00->7F", "3 state 7F->05"}));
  EXPECT_EQ(m.state(), kNmtOperational);

  CanSink none = {nullptr, nullptr};  // heartbeat monitors never send
  now = 510000 + 749999;
  m.process(now, none, l);
  EXPECT_TRUE(events.take().empty());
  now += 1;
  m.process(now, none, l);
  EXPECT_EQ(events.take(), Strings({"3 lost 05->05"}));
  // A heartbeat after the loss: back (same state: no state change).
  now += 2000000;
  m.on_frame(F(0x703, {0x05}), now, l);
  EXPECT_EQ(events.take(), Strings({"3 back 05->05"}));
}

TEST(MasterMonitorConfig, RefusesWhatCiA301DoesNotAllow) {
  NodeMonitor m;
  EXPECT_FALSE(m.watch_heartbeat(0, 100, 150));
  EXPECT_FALSE(m.watch_heartbeat(128, 100, 150));
  EXPECT_FALSE(m.watch_heartbeat(3, 100, 100)) << "consumer time must exceed producer time";
  EXPECT_FALSE(m.watch_heartbeat(3, 0, 100));
  EXPECT_FALSE(m.watch_guarding(3, 0, 3));
  EXPECT_FALSE(m.watch_guarding(3, 100, 0));
  EXPECT_EQ(m.link(), kLinkOff);
  EXPECT_TRUE(m.watch_heartbeat(3, 100, 150));
  EXPECT_EQ(m.producer_ms(), 100u);
  EXPECT_FALSE(m.watch_guarding(3, 100, 0));
  EXPECT_EQ(m.link(), kLinkWaiting) << "a refused configuration changes nothing";
  EXPECT_FALSE(m.guarding());
}

TEST_F(MasterMonitor, NodesNotArmedRaiseNothing) {
  // Node 4 is watched but never speaks; node 3 speaks but is not watched.
  ASSERT_TRUE(table.monitor(4)->watch_heartbeat(4, 100, 150));
  bus.add_node(3);
  sdo_to_node3({0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00});  // 1017h = 100 ms
  bus.run(10000000, 1000);
  uint32_t t = 0;
  EXPECT_TRUE(bus.last_time_of("<703> 7F", &t)) << "node 3 does send heartbeats";
  EXPECT_TRUE(events.take().empty());
  EXPECT_EQ(table.find(4)->link(), kLinkWaiting);
  EXPECT_EQ(table.find(3), nullptr);
  EXPECT_FALSE(table.on_frame(F(0x703, {0x7F}), bus.now));
  NextDeadline d(bus.now);
  table.next_deadline(d);
  EXPECT_FALSE(d.result(&t)) << "nothing armed: no deadline";
}

TEST_F(MasterMonitor, GuardingARealNodeTogglesAndLosesItExactlyAfterTheLifeTime) {
  MasterBus::Station& node = bus.add_node(3);
  sdo_to_node3({0x2B, 0x0C, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00});  // 100Ch guard time 100 ms
  sdo_to_node3({0x2F, 0x0D, 0x10, 0x00, 0x03, 0x00, 0x00, 0x00});  // 100Dh life time factor 3
  bus.take();
  events.take();
  ASSERT_TRUE(table.monitor(3)->watch_guarding(3, 100, 3));
  EXPECT_EQ(table.find(3)->producer_ms(), 0u);
  bus.step(100);
  bus.run(300000 - 100);
  // An RTR every guard time, answered with the state and an alternating toggle bit.
  EXPECT_EQ(bus.take(), Strings({"<703> RTR", "<703> 7F", "<703> RTR", "<703> FF", "<703> RTR", "<703> 7F"}));
  EXPECT_EQ(events.take(), Strings({"3 state FF->7F"}));
  ASSERT_TRUE(nmt.start(3));
  bus.run(1000000);
  EXPECT_EQ(events.take(), Strings({"3 state 7F->05"}));
  EXPECT_EQ(table.find(3)->toggle_errors(), 0u);
  Strings frames = bus.take();
  EXPECT_EQ(std::count(frames.begin(), frames.end(), std::string("<703> RTR")), 10);
  for (const std::string& f : frames)
    EXPECT_EQ(f.find("<083>"), std::string::npos) << "no life guarding EMCY";

  // The node falls off: lost guard time x life time factor after its last answer.
  uint32_t with_toggle = 0;
  uint32_t without = 0;
  ASSERT_TRUE(bus.last_time_of("<703> 85", &with_toggle));
  ASSERT_TRUE(bus.last_time_of("<703> 05", &without));
  const uint32_t last = std::max(with_toggle, without);
  node.plugged = false;
  expect_exactly_at(last + 300000u, "3 lost 05->05");
  // RTRs go on while it is lost; its first answer brings it back, whatever
  // its toggle (it may have been reset unseen).
  node.plugged = true;
  bus.run(100000);
  EXPECT_EQ(events.take(), Strings({"3 back 05->05"}));
  EXPECT_EQ(table.find(3)->toggle_errors(), 0u);
}

TEST_F(MasterMonitor, GuardingAnswerWithTheSameToggleTwiceIsAToggleErrorThatDoesNotKeepTheNodeAlive) {
  MasterBus::Station& node = bus.add_node(3);
  sdo_to_node3({0x2B, 0x0C, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00});
  sdo_to_node3({0x2F, 0x0D, 0x10, 0x00, 0x03, 0x00, 0x00, 0x00});
  ASSERT_TRUE(table.monitor(3)->watch_guarding(3, 100, 3));
  bus.run(250000);  // RTRs at 0.1, 100.1, 200.1 ms: answers 7F, FF, 7F
  events.take();
  uint32_t last = 0;
  ASSERT_TRUE(bus.last_time_of("<703> 7F", &last));
  EXPECT_EQ(last, bus.now - 50000u + 100u);
  // A repeated answer (toggle 0 again) is not a valid one...
  bus.inject(F(0x703, {0x7F}));
  EXPECT_EQ(events.take(), Strings({"3 toggle 7F->7F"}));
  EXPECT_EQ(table.find(3)->toggle_errors(), 1u);
  // ...so the life time still runs from the last valid answer.
  node.plugged = false;
  expect_exactly_at(last + 300000u, "3 lost 7F->7F");
}

TEST(MasterMonitorGuarding, BootUpResetsTheExpectedToggle) {
  uint32_t now = 0;
  EventLog events(&now);
  const MonitorListener l = events.listener();
  FrameLog log;
  NodeMonitor m;
  ASSERT_TRUE(m.watch_guarding(5, 100, 2));
  m.process(now, log.sink(), l);
  EXPECT_EQ(log.take(), Strings({"<705> RTR"}));
  EXPECT_EQ(log.frames.size(), 0u);
  m.on_frame(F(0x705, {0x7F}), now, l);  // toggle 0
  m.on_frame(F(0x705, {0xFF}), now, l);  // toggle 1
  m.on_frame(F(0x705, {0x00}), now, l);  // boot-up
  m.on_frame(F(0x705, {0x7F}), now, l);  // toggle 0 again: right after a boot-up
  EXPECT_EQ(events.take(), Strings({"5 state FF->7F", "5 boot-up 7F->00", "5 state 00->7F"}));
  EXPECT_EQ(m.toggle_errors(), 0u);
  m.on_frame(F(0x705, {0x7F}), now, l);  // toggle 0 twice
  EXPECT_EQ(events.take(), Strings({"5 toggle 7F->7F"}));
  m.on_frame(F(0x705, {0xFF}), now, l);  // resynchronised: alternating from the wrong one
  EXPECT_TRUE(events.take().empty());
  EXPECT_EQ(m.toggle_errors(), 1u);
}

TEST(MasterMonitorGuarding, RtrEveryGuardTimeAndARefusedOneIsRetried) {
  uint32_t now = 1000;
  FrameLog log;
  const MonitorListener none = {nullptr, nullptr};
  NodeMonitor m;
  ASSERT_TRUE(m.watch_guarding(5, 100, 2));
  NextDeadline d0(now);
  m.next_deadline(d0);
  uint32_t at = 0;
  ASSERT_TRUE(d0.result(&at));
  EXPECT_EQ(at, now) << "the first RTR is due at once";
  m.process(now, log.sink(), none);
  EXPECT_EQ(log.take(), Strings({"<705> RTR"}));
  ASSERT_EQ(log.frames.size(), 0u);
  NextDeadline d1(now);
  m.next_deadline(d1);
  ASSERT_TRUE(d1.result(&at));
  EXPECT_EQ(at, now + 100000u);
  m.process(now + 99999u, log.sink(), none);
  EXPECT_TRUE(log.take().empty());
  log.refuse = true;
  m.process(now + 100000u, log.sink(), none);
  EXPECT_EQ(m.send_failures(), 1u);
  log.refuse = false;
  m.process(now + 100500u, log.sink(), none);
  EXPECT_EQ(log.take(), Strings({"<705> RTR"}));
  m.process(now + 200000u, log.sink(), none);
  EXPECT_EQ(log.take(), Strings({"<705> RTR"})) << "the period keeps its phase";
}

TEST_F(MasterMonitor, ATableWatchesSeveralRealNodesEachOnItsOwn) {
  MasterBus::Station& n3 = bus.add_node(3);
  bus.add_node(5);
  ASSERT_TRUE(table.monitor(3)->watch_heartbeat(3, 100, 150));
  ASSERT_TRUE(table.monitor(5)->watch_heartbeat(5, 100, 150));
  EXPECT_EQ(table.monitor(3), table.monitor(3)) << "one monitor per node id";
  EXPECT_EQ(table.monitor(0), nullptr);
  EXPECT_EQ(table.monitor(128), nullptr);
  n3.io.node().local_nmt(kNmtStart, bus.now);
  for (int id : {3, 5}) {
    const uint8_t req[8] = {0x2B, 0x17, 0x10, 0x00, 0x64, 0x00, 0x00, 0x00};
    ASSERT_TRUE(send_frame(sink, static_cast<uint16_t>(0x600 + id), 8, req));
  }
  bus.run(1000000);
  // Both boot-ups came before the monitors were set up: unknown, then heard.
  EXPECT_EQ(events.take(), Strings({"3 state FF->05", "5 state FF->7F"}));
  EXPECT_EQ(table.find(3)->state(), kNmtOperational);
  EXPECT_EQ(table.find(5)->state(), kNmtPreOperational);
  n3.plugged = false;
  bus.run(200000);
  EXPECT_EQ(events.take(), Strings({"3 lost 05->05"}));
  EXPECT_EQ(table.find(5)->link(), kLinkAlive);
  EXPECT_EQ(table.lost_count(), 1u);
}

TEST(MasterMonitorTable, All127NodesAtOnce) {
  uint32_t now = 0;
  EventLog events(&now);
  NodeMonitorTable<127> table;
  table.set_listener(events.listener());
  for (uint8_t id = 1; id <= 127; ++id) ASSERT_TRUE(table.monitor(id)->watch_heartbeat(id, 100, 200));
  EXPECT_EQ(table.monitor(1), table.find(1));
  for (uint8_t id = 1; id <= 127; ++id) EXPECT_TRUE(table.on_frame(F(0x700u + id, {0x7F}), now));
  EXPECT_EQ(events.take().size(), 127u);
  const CanSink none = {nullptr, nullptr};
  now = 150000;
  for (uint8_t id = 2; id <= 127; ++id) table.on_frame(F(0x700u + id, {0x7F}), now);
  now = 200000;
  table.process(now, none);
  EXPECT_EQ(events.take(), Strings({"1 lost 7F->7F"}));
  now = 350000;
  table.process(now, none);
  EXPECT_EQ(events.take().size(), 126u);
  EXPECT_EQ(table.lost_count(), 127u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
