// mb2co-master serve against a node that is not ours: npm's canopen SDO
// server (tests/peers/canopen_peer.js, node 34) on vcan0, asked by a
// CiA 309-3 client that is not ours either (serve_client.py). Expedited,
// segmented and block reads and writes; what a write stored is read back by
// npm's own client, the 4 KiB domain compared with the server's pattern
// decoded by the test's own base64. ctest runs this binary inside
// hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>

#include "node_harness.h"
#include "npm_peer.h"
#include "serve_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kNpmNode = 34;
const std::string kNode = std::to_string(kNpmNode);
constexpr size_t kDomain = 4096;

TEST(MasterServeNpm, ReadsAndWritesOfNpmsServerThroughServe) {
  TempDir dir;
  LineChild server;
  ASSERT_TRUE(server.start(peer_command({"server", "--node", kNode, "--size", std::to_string(kDomain)})))
      << server.error();
  ASSERT_TRUE(server.wait_prefix("ready node=", kPeerDeadline)) << server.stderr_text();
  ServeProcess serve;
  ASSERT_TRUE(serve.start("unix:" + dir.path("S"))) << serve.error();
  ServeClient c;
  ASSERT_TRUE(c.open(serve.where()));

  EXPECT_EQ(c.ask("[1] " + kNode + " r 0x2001 0 x32"), "[1] 0x12345678");           // expedited
  EXPECT_EQ(c.ask("[2] " + kNode + " r 0x1008 0 vs"), "[2] \"npm canopen peer\"");  // segmented
  EXPECT_EQ(c.ask("[3] " + kNode + " r 0x3000 0 u32"),
            "[3] ERROR:0x06020000 #object does not exist in the object dictionary");
  EXPECT_EQ(c.ask("[4] " + kNode + " w 0x2001 0 u32 0xCAFE0042"), "[4] OK");
  std::string stored;
  ASSERT_TRUE(server.wait_prefix("stored index=2001 sub=0 ", kPeerDeadline, &stored));
  PeerResult p = run_peer_client({"upload", "--node", kNode, "--index", "0x2001", "--sub", "0"});
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  EXPECT_EQ(p.field("data"), "4200feca") << "npm's client reads what serve wrote";
  EXPECT_EQ(c.ask("[5] " + kNode + " w 0x2002 0 vs \"by mb2co 11\""), "[5] OK");  // segmented
  ASSERT_TRUE(server.wait_prefix("stored index=2002 sub=0 ", kPeerDeadline, &stored));
  p = run_peer_client({"upload", "--node", kNode, "--index", "0x2002", "--sub", "0"});
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  EXPECT_EQ(p.field("data"), to_hex({'b', 'y', ' ', 'm', 'b', '2', 'c', 'o', ' ', '1', '1'}));

  // Its 4 KiB domain block-wise (with CRC), then segmented: the pattern.
  EXPECT_EQ(c.ask("[6] set sdo_block 1"), "[6] OK");
  std::string answer = c.ask("[7] " + kNode + " r 0x1F50 1 d");
  ASSERT_EQ(answer.rfind("[7] ", 0), 0u) << answer.substr(0, 100);
  EXPECT_TRUE(base64_bytes(answer.substr(4)) == peer_pattern(kDomain)) << "block: not the server's pattern";
  EXPECT_EQ(c.ask("[8] set sdo_block 0"), "[8] OK");
  answer = c.ask("[9] " + kNode + " r 0x1F50 1 d");
  EXPECT_TRUE(base64_bytes(answer.substr(4)) == peer_pattern(kDomain))
      << "segmented: not the server's pattern";

  // A block download of 1000 bytes of other content, read back by npm.
  const std::vector<uint8_t> content = other_content(1000, 7);
  std::string hex;
  for (const uint8_t b : content) {
    static const char digits[] = "0123456789ABCDEF";
    hex += digits[b >> 4];
    hex += digits[b & 15];
  }
  EXPECT_EQ(c.ask("[10] set sdo_block 1"), "[10] OK");
  EXPECT_EQ(c.ask("[11] " + kNode + " w 0x1F50 1 hex " + hex), "[11] OK");
  ASSERT_TRUE(server.wait_prefix("stored index=1F50 sub=1 ", kPeerDeadline, &stored));
  EXPECT_EQ(field_of(stored, "bytes"), "1000") << stored;
  const std::string file = dir.path("back.bin");
  p = run_peer_client(
      {"upload", "--node", kNode, "--index", "0x1F50", "--sub", "1", "--block", "--file", file});
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  EXPECT_TRUE(read_file(file) == content) << "npm's client does not read what serve wrote";
  EXPECT_EQ(c.ask("[12] " + kNode + " start"), "[12] OK");
  EXPECT_EQ(serve.stop(), 0);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
