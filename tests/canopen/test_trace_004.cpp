// Seed 004 §2.11: the frame exchange between a master (id 1) and a CiA 401
// digital I/O module with node id 3, replayed byte for byte.
#include <gtest/gtest.h>

#include "frame_log.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using test::F;
using Frames = std::vector<std::string>;

TEST(Trace004, ReplaysTheWorkedFrameExchangeByteForByte) {
  test::FrameLog bus;
  ionode::IoNode node(bus.sink(), 0x00030191u);
  uint32_t t = 0;

  node.start(3, t);
  EXPECT_EQ(bus.take(), Frames({"<703> 00"}));  // boot-up

  t += 1000;
  node.receive(F(0x603, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}), t);  // read 1000h
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<583> 42 00 10 00 91 01 03 00"}));

  t += 1000;
  node.receive(F(0x603, {0x22, 0x17, 0x10, 0x00, 0xF4, 0x01, 0x00, 0x00}), t);  // 1017h = 500
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<583> 60 17 10 00 00 00 00 00"}));

  t += 500000;  // one heartbeat period later
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<703> 7F"}));

  t += 1000;
  node.receive(F(0x000, {0x01, 0x03}), t);  // NMT start node 3
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<183> 00 00"}));  // TPDO1 on entering operational

  t += 499000;
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<703> 05"}));

  t += 1000;
  node.set_input(0, 0x02);
  node.set_input(1, 0x81);  // three input pins high
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({"<183> 02 81"}));

  t += 1000;
  node.receive(F(0x203, {0x00, 0x01}), t);  // RPDO1 sets one output
  node.process(t);
  EXPECT_EQ(bus.take(), Frames({}));
  EXPECT_EQ(node.output(0), 0x00);
  EXPECT_EQ(node.output(1), 0x01);
}

}  // namespace
}  // namespace mb2co
