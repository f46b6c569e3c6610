// The serial data link allocates nothing at run time: every allocation
// function is hooked (tests/support/alloc_hooks.h, as for the core in
// tests/canopen_noheap), and three I/O nodes polled over SerialLinks
// (boot-up, NMT, heartbeats, a PDO from node to node, SDO expedited and
// segmented uploads) must make zero calls. The line here is a fixed array:
// the test itself does not allocate while counting.
#include <gtest/gtest.h>
#include <string.h>

#include "../../support/alloc_hooks.h"
#include "canopen/sdo_client.h"
#include "ionode/io_node.h"
#include "serialnet/serial_link.h"

namespace mb2co {
namespace serialnet {
namespace {

const int kStations = 3;

// One talker at a time (the polling guarantees it); bytes reach the others
// when their last bit has arrived. Fixed capacity.
struct Line {
  struct Byte {
    uint32_t at_us;
    uint8_t value;
    uint8_t talker;
  };
  Byte bytes[512];
  int head = 0, tail = 0;  // ring [head, tail)
  uint32_t now = 0;
  uint32_t byte_us = byte_time_us(115200);
  uint32_t line_free_us = 0;
  SerialLink* links[kStations] = {};
  struct Port {
    Line* line;
    uint8_t index;
  } ports[kStations];

  modbus::ByteSink port(uint8_t i) {
    ports[i] = Port{this, i};
    return modbus::ByteSink{&Line::write, &ports[i]};
  }
  static bool write(void* ctx, const uint8_t* d, uint16_t n) {
    Port& p = *static_cast<Port*>(ctx);
    Line& l = *p.line;
    uint32_t t = time_reached(l.now, l.line_free_us) ? l.now : l.line_free_us;
    for (uint16_t i = 0; i < n; ++i) {
      t += l.byte_us;
      l.bytes[l.tail % 512] = Byte{t, d[i], p.index};
      ++l.tail;
    }
    l.line_free_us = t;
    return true;
  }
  void deliver() {
    while (head != tail && time_reached(now, bytes[head % 512].at_us)) {
      const Byte& b = bytes[head % 512];
      for (int i = 0; i < kStations; ++i) {
        if (i != b.talker) links[i]->on_byte(b.value, b.at_us);
      }
      ++head;
    }
  }
};

struct Station {
  Station(Line& line, uint8_t index, const BusConfig& config)
      : link(config, static_cast<uint8_t>(index + 1), line.port(index)), io(link.can_sink()) {
    line.links[index] = &link;
    link.set_receiver(CanReceiver{&Station::receive, this});
  }
  static void receive(void* ctx, const CanFrame& f, uint32_t now_us) {
    Station& s = *static_cast<Station*>(ctx);
    s.io.receive(f, now_us);
    if (s.client_on) s.client.on_frame(f, now_us, s.link.can_sink());
  }
  void process(uint32_t now_us) {
    io.process(now_us);
    if (client_on) client.process(now_us, link.can_sink());
    link.process(now_us);
  }
  SerialLink link;
  ionode::IoNode io;
  canopen::SdoClient client{};
  bool client_on = false;
};

TEST(SerialNetNoHeap, PolledNodesExchangeEverythingWithoutAllocating) {
  BusConfig c = {};
  c.set = connection_set(IdBits::k7);
  c.baud = 115200;
  c.first_node = 1;
  c.last_node = kStations;
  c.window_us = 3000;
  c.guard_us = 100;
  static Line line;
  c.access = Access::kPoller;
  static Station s1(line, 0, c);
  c.access = Access::kPolled;
  static Station s2(line, 1, c);
  static Station s3(line, 2, c);
  Station* all[kStations] = {&s1, &s2, &s3};
  uint8_t name[32] = {};
  uint8_t vendor[4] = {};

  g_calls = 0;
  g_counting = true;
  for (Station* s : all) {
    s->io.start(s->link.node_id(), 0);
    const uint8_t overflow = kStations;
    s->io.od().write(0x1019, 0, &overflow, 1);
    const uint8_t hb[2] = {100, 0};
    s->io.od().write(0x1017, 0, hb, 2);
  }
  uint8_t cob[4];
  canopen::put_le32(cob, 0x80000202u);
  s2.io.od().write(0x1400, 1, cob, 4);
  canopen::put_le32(cob, 0x181u);
  s2.io.od().write(0x1400, 1, cob, 4);
  CanFrame start = {};
  start.dlc = 2;
  start.data[0] = canopen::kNmtStart;
  s1.link.send(start);
  s1.io.node().local_nmt(canopen::kNmtStart, 0);
  s1.client_on = true;
  bool uploaded_name = false;
  for (line.now = 0; line.now < 2000000; line.now += 10) {
    line.deliver();
    for (Station* s : all) s->process(line.now);
    if (line.now == 200000) {
      s1.io.set_input(0, 0x77);
      s1.client.init(2);
      s1.client.start_upload(0x1008, 0, canopen::kSdoAuto, name, sizeof name, line.now, s1.link.can_sink());
    }
    if (line.now > 200000 && !uploaded_name && !s1.client.busy()) {
      uploaded_name = true;
      s1.client.init(3);
      s1.client.start_upload(0x1018, 1, canopen::kSdoAuto, vendor, sizeof vendor, line.now,
                             s1.link.can_sink());
    }
  }
  g_counting = false;
  EXPECT_EQ(g_calls, 0);
  // The scenario really ran: operational, the PDO arrived, both uploads done.
  for (Station* s : all) EXPECT_EQ(s->io.node().nmt_state(), canopen::kNmtOperational);
  EXPECT_EQ(s2.io.output(0), 0x77);
  EXPECT_TRUE(uploaded_name);
  EXPECT_EQ(std::string(reinterpret_cast<char*>(name), 14), "mb2co I/O node");
  EXPECT_EQ(s1.client.status(), canopen::SdoClient::kDone);
  EXPECT_EQ(s1.client.transferred(), 4u);
  EXPECT_GT(s3.link.counters().windows, 100);
}

}  // namespace
}  // namespace serialnet
}  // namespace mb2co
