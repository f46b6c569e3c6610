// The lab's PDO and SDO functions (seed 000 §4.2-4.5: pdo_send, pdo_recv,
// sdo_read, sdo_write) on two I/O nodes, A and B, written the way the
// seed's exercises are: A sends SYNC and calls pdo_recv(); B answers with
// its synchronous TPDO (the "joystick", 6000h); A's RPDO maps it onto its
// "leds" (6200h). The bus between them is virtual: every read of A's clock
// lets time pass and lets B run, as the second Arduino would meanwhile.
#include <gtest/gtest.h>

#include <cstring>
#include <deque>
#include <string>
#include <vector>

#include "canopen/lab_api.h"
#include "canopen/od_lab_api.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using namespace canopen;

struct TwoBoards {
  std::deque<CanFrame> to_a, to_b;
  std::vector<CanFrame> sent_by_a, sent_by_b;
  uint32_t now = 0;
  bool b_plugged = true;

  static bool a_sends(void* ctx, const CanFrame& f) {
    TwoBoards& w = *static_cast<TwoBoards*>(ctx);
    w.sent_by_a.push_back(f);
    if (w.b_plugged) w.to_b.push_back(f);
    return true;
  }
  static bool b_sends(void* ctx, const CanFrame& f) {
    TwoBoards& w = *static_cast<TwoBoards*>(ctx);
    w.sent_by_b.push_back(f);
    w.to_a.push_back(f);
    return true;
  }
  ionode::IoNode a{CanSink{&TwoBoards::a_sends, this}};
  ionode::IoNode b{CanSink{&TwoBoards::b_sends, this}};

  // B, the second Arduino, runs whenever A looks at its clock.
  void run_b() {
    while (!to_b.empty()) {
      const CanFrame f = to_b.front();
      to_b.pop_front();
      b.receive(f, now);
    }
    b.process(now);
  }
  static uint32_t clock(void* ctx) {
    TwoBoards& w = *static_cast<TwoBoards*>(ctx);
    w.now += 50;  // a loop pass of A
    w.run_b();
    return w.now;
  }
  static bool receive(void* ctx, CanFrame* f) {
    TwoBoards& w = *static_cast<TwoBoards*>(ctx);
    if (w.to_a.empty()) return false;
    *f = w.to_a.front();
    w.to_a.pop_front();
    return true;
  }
  LabBus bus{CanSink{&TwoBoards::a_sends, this}, &TwoBoards::receive, &TwoBoards::clock, this};
};

class LabPdoSdo : public ::testing::Test {
 protected:
  TwoBoards w;
  void SetUp() override {
    w.a.start(1, 0);
    w.b.start(2, 0);
    // Both operational (the lab's master would send NMT start).
    w.a.node().local_nmt(kNmtStart, 0);
    w.b.node().local_nmt(kNmtStart, 0);
    w.run_b();
    w.to_a.clear();
    w.sent_by_a.clear();
    w.sent_by_b.clear();
    lab_bind(&w.a.node(), &w.bus);
  }
  void TearDown() override {
    lab_bind(nullptr, nullptr);
    od_bind(nullptr);
  }
  // Week 12 §4.1/§4.4 configuration, with the OD functions of week 11.
  void configure_sync_pdo_from_b_to_a() {
    od_bind(&w.b.od());
    const uint8_t type_sync = 1;  // B: TPDO1 at every SYNC
    ASSERT_EQ(od_write_subentry(0x1800, 2, &type_sync), 0);
    od_bind(&w.a.od());
    // A: RPDO1 listens to B's TPDO1 (COB-ID 182h), mapping 6200h/1..2.
    const uint8_t invalid[4] = {0x02, 0x02, 0x00, 0x80};
    ASSERT_EQ(od_write_subentry(0x1400, 1, invalid), 0);
    const uint8_t from_b[4] = {0x82, 0x01, 0x00, 0x00};
    ASSERT_EQ(od_write_subentry(0x1400, 1, from_b), 0);
  }
};

TEST_F(LabPdoSdo, SyncFromAMakesBsJoystickLightAsLeds) {
  configure_sync_pdo_from_b_to_a();
  w.b.set_input(0, 0x05);  // B's joystick
  w.b.set_input(1, 0xA0);
  // A's program of §4.4: send SYNC, then pdo_recv().
  const CanFrame sync{0x080, 0, 0, {}};
  ASSERT_TRUE(w.bus.send.send(w.bus.send.ctx, sync));
  w.clock(&w);  // the SYNC reaches B, which answers
  EXPECT_EQ(pdo_recv(), 1) << "B's TPDO1 arrived";
  uint8_t leds[2] = {0, 0}, size = 0;
  ASSERT_EQ(od_read_subentry(0x6200, 1, &leds[0], &size), 0);
  ASSERT_EQ(od_read_subentry(0x6200, 2, &leds[1], &size), 0);
  EXPECT_EQ(leds[0], 0x05);
  EXPECT_EQ(leds[1], 0xA0);
  ASSERT_EQ(w.sent_by_b.size(), 1u);
  EXPECT_EQ(w.sent_by_b[0].id, 0x182u);
}

TEST_F(LabPdoSdo, PdoSendBuildsTheTpdoFromItsMappingAndSendsItNow) {
  w.a.set_input(0, 0x11);
  w.a.set_input(1, 0x22);
  w.sent_by_a.clear();
  ASSERT_EQ(pdo_send(0x1800), 0);
  ASSERT_EQ(pdo_send(0x1A00), 0) << "the mapping record names the same TPDO";
  ASSERT_EQ(w.sent_by_a.size(), 2u);
  for (const CanFrame& f : w.sent_by_a) {
    EXPECT_EQ(f.id, 0x181u);
    ASSERT_EQ(f.dlc, 2);
    EXPECT_EQ(f.data[0], 0x11);
    EXPECT_EQ(f.data[1], 0x22);
  }
  EXPECT_EQ(pdo_send(0x1234), kLabNoPdo);
  EXPECT_EQ(pdo_send(0x1804), kLabNoPdo) << "the ionode has TPDO1-4, 1804h is none";
  // TPDO2 has nothing mapped on the I/O node: nothing to send.
  EXPECT_EQ(pdo_send(0x1801), kLabPdoInvalid);
  w.a.node().local_nmt(kNmtEnterPreOperational, w.now);
  w.sent_by_a.clear();
  EXPECT_EQ(pdo_send(0x1800), kLabNotOperational);
  EXPECT_TRUE(w.sent_by_a.empty());
}

TEST_F(LabPdoSdo, SdoReadAndWriteReachTheOtherBoard) {
  uint8_t data[32];
  uint8_t size = sizeof data;
  ASSERT_EQ(sdo_read(2, 0x1008, 0, data, &size), 0);  // device name: segmented
  uint8_t name[32], name_size = 0;
  od_bind(&w.b.od());
  ASSERT_EQ(od_read_subentry(0x1008, 0, name, &name_size), 0);
  ASSERT_GT(size, 4) << "longer than an expedited transfer";
  EXPECT_EQ(std::string(reinterpret_cast<char*>(data), size),
            std::string(reinterpret_cast<char*>(name), strnlen(reinterpret_cast<char*>(name), name_size)));

  const uint8_t hb[2] = {0xF4, 0x01};  // 500 ms
  ASSERT_EQ(sdo_write(2, 0x1017, 0, hb, 2), 0);
  uint8_t back[2] = {0, 0};
  size = 2;
  ASSERT_EQ(sdo_read(2, 0x1017, 0, back, &size), 0);
  EXPECT_EQ(size, 2);
  EXPECT_EQ(back[0], 0xF4);
  EXPECT_EQ(back[1], 0x01);

  // The server's abort comes back with its code.
  size = sizeof data;
  EXPECT_EQ(sdo_read(2, 0x1234, 0, data, &size), kLabSdoFailed);
  EXPECT_EQ(lab_sdo_abort(), 0x06020000u);
  // A board that is not there: the client's timeout.
  w.b_plugged = false;
  size = sizeof data;
  EXPECT_EQ(sdo_read(2, 0x1017, 0, data, &size), kLabSdoFailed);
  EXPECT_EQ(lab_sdo_abort(), 0x05040000u);
}

TEST_F(LabPdoSdo, ABoardKeepsBeingServedWhileItsSdoRequestWaits) {
  configure_sync_pdo_from_b_to_a();
  // B asks A's 1018h/1 by SDO while A's own sdo_read runs: A's node answers.
  // (B's request is injected into A's queue as B's SDO client would send it.)
  w.to_a.push_back(CanFrame{0x601, 8, 0, {0x40, 0x18, 0x10, 0x01, 0, 0, 0, 0}});
  uint8_t data[4];
  uint8_t size = sizeof data;
  ASSERT_EQ(sdo_read(2, 0x1017, 0, data, &size), 0);
  bool answered = false;
  // An expedited upload response (scs 2, e set) for 1018h/1.
  for (const CanFrame& f : w.sent_by_a)
    answered =
        answered || (f.id == 0x581 && (f.data[0] & 0xE2) == 0x42 && f.data[1] == 0x18 && f.data[2] == 0x10);
  EXPECT_TRUE(answered) << "A's SDO server answered during A's own transfer";
}

TEST(LabPdoSdoUnbound, EveryFunctionSaysNotBound) {
  lab_bind(nullptr, nullptr);
  uint8_t data[4];
  uint8_t size = 4;
  EXPECT_EQ(pdo_send(0x1800), kLabNotBound);
  EXPECT_EQ(pdo_recv(), kLabNotBound);
  EXPECT_EQ(sdo_read(2, 0x1017, 0, data, &size), kLabNotBound);
  EXPECT_EQ(sdo_write(2, 0x1017, 0, data, 2), kLabNotBound);
}

}  // namespace
}  // namespace mb2co
