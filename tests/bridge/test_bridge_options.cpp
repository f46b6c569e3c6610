// mb2co-bridge's command line (firmware/linux/bridge, on the shared layer of
// docs/cli.md): the segment and CAN options reach the bridge's
// configuration, and every bad input is refused with one line that names the
// option, by the parser (a usage error) or by the checks after it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bridge_options.h"

namespace mb2co {
namespace bridge {
namespace {

Status parse(std::vector<const char*> args, BridgeOptions* o, serialnet::BridgeConfig* c) {
  args.insert(args.begin(), "mb2co-bridge");
  const cli::Parsed p = cli::parse(bridge_program(), static_cast<int>(args.size()), args.data());
  if (p.action == cli::Action::kUsageError) return Status::failure(p.text);
  EXPECT_EQ(p.action, cli::Action::kRun);
  Status s = apply_bridge_options(p.args, o);
  if (s) s = bridge_config(*o, c);
  return s;
}

TEST(BridgeOptions, SegmentAndCanOptionsMakeTheBridgeConfig) {
  BridgeOptions o;
  serialnet::BridgeConfig c = {};
  ASSERT_TRUE(parse({"--serial",    "/dev/ttyUSB0", "--can",      "can1", "--bits",    "7",
                     "--access",    "token",        "--nodes",    "2-9",  "--offset",  "64",
                     "--window-us", "8000",         "--guard-us", "400",  "--forward", "0x185,0x285,900",
                     "--echo",      "--baud",       "57600"},
                    &o, &c))
      << "parsed";
  EXPECT_EQ(o.can, "can1");
  EXPECT_EQ(c.bus.set.id_bits, 7);
  EXPECT_EQ(c.bus.access, serialnet::Access::kTokenStarter);
  EXPECT_EQ(c.bus.first_node, 2);
  EXPECT_EQ(c.bus.last_node, 10) << "the bridge's window follows the nodes";
  EXPECT_EQ(c.bridge_node, 10);
  EXPECT_EQ(c.node_offset, 0x40);
  EXPECT_EQ(c.bus.window_us, 8000u);
  EXPECT_EQ(c.bus.guard_us, 400u);
  EXPECT_EQ(c.bus.baud, 57600u);
  ASSERT_EQ(c.extra_count, 3);
  EXPECT_EQ(c.extra_to_serial[0], 0x185);
  EXPECT_EQ(c.extra_to_serial[1], 0x285);
  EXPECT_EQ(c.extra_to_serial[2], 900);
  EXPECT_TRUE(o.segment.echo);
}

TEST(BridgeOptions, DefaultsPollTheEightBitSet) {
  BridgeOptions o;
  serialnet::BridgeConfig c = {};
  ASSERT_TRUE(parse({"--pty", "/tmp/seg"}, &o, &c));
  EXPECT_EQ(c.bus.set.id_bits, 8);
  EXPECT_EQ(c.bus.access, serialnet::Access::kPoller);
  EXPECT_EQ(c.bridge_node, 4);
  EXPECT_EQ(o.can, "vcan0");
}

TEST(BridgeOptions, BadInputIsOneLineNamingTheOption) {
  struct Case {
    std::vector<const char*> args;
    const char* names;
  };
  const Case cases[] = {
      {{"--serial", "x", "--bits", "9"}, "--bits"},
      {{"--serial", "x", "--access", "ring"}, "--access"},
      {{"--serial", "x", "--nodes", "3-1"}, "--nodes"},
      {{"--serial", "x", "--bits", "7", "--nodes", "1-15"}, "--nodes"},  // + the bridge: 16 > 15 nodes
      {{"--serial", "x", "--offset", "200"}, "--offset"},
      {{"--serial", "x", "--nodes", "1-30", "--offset", "100"}, "--offset"},
      {{"--serial", "x", "--window-us", "100"}, "--window-us"},
      {{"--serial", "x", "--forward", "0x800"}, "--forward"},
      {{"--serial", "x", "--forward", "0x185,"}, "--forward"},
      {{"--serial", "x", "--forward", "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17"}, "--forward"},
      {{"--serial", "x", "--offset", "0x40"}, "--offset"},
      {{"--serial", "x", "--baud", "600"}, "--baud"},
      {{"--serial", "x", "--can"}, "--can"},
      {{"--serial", "x", "--can", "can0", "--can", "can1"}, "--can"},
      {{"--serial", "x", "--pty", "y"}, "--pty"},
      {{}, "--serial"},
      {{"--serial", "x", "--frobnicate"}, "--frobnicate"},
      {{"--serial"}, "--serial"},
  };
  for (const Case& k : cases) {
    BridgeOptions o;
    serialnet::BridgeConfig c = {};
    const Status s = parse(k.args, &o, &c);
    ASSERT_FALSE(s) << k.names;
    EXPECT_NE(s.message().find(k.names), std::string::npos) << s.message();
    EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
  }
}

}  // namespace
}  // namespace bridge
}  // namespace mb2co
