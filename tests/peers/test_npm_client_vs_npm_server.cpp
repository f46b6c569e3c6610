// npm's canopen SDO client against npm's canopen SDO server on vcan0 (ctest
// peers.npm_client_vs_npm_server, inside hil/uml/run-with-vcan.sh): proves
// the peer itself (both roles, every transfer kind, 64 KiB block transfers
// whose CRC npm checks at the end) before it judges mb2co's side. The rates
// it prints are the reference for the SDO benchmark on the same bus.
#include <gtest/gtest.h>

#include <iostream>

#include "node_harness.h"
#include "npm_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kServerNode = 0x22;
constexpr size_t kBig = 64 * 1024;

class NpmClientVsNpmServer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    server_ = new LineChild();
    ASSERT_TRUE(server_->start(
        peer_command({"server", "--node", std::to_string(kServerNode), "--size", std::to_string(kBig)})))
        << server_->error();
    ASSERT_TRUE(server_->wait_prefix("ready node=", kPeerDeadline)) << server_->stderr_text();
  }
  static void TearDownTestSuite() {
    delete server_;  // kills and reaps it
    delete dir_;
    server_ = nullptr;
    dir_ = nullptr;
  }
  static std::vector<std::string> args(const char* op, const char* index, int sub) {
    return {op, "--node", std::to_string(kServerNode), "--index", index, "--sub", std::to_string(sub)};
  }
  /// A 64 KiB transfer of 1F50h/1; `block` or segmented.
  static PeerResult big(const char* op, bool block, const std::string& file) {
    std::vector<std::string> a = args(op, "0x1F50", 1);
    if (block) a.push_back("--block");
    a.insert(a.end(), {"--file", file, "--timeout", "5000"});
    const PeerResult r = run_peer_client(a);
    std::cout << "npm client " << (block ? "block" : "segmented") << " " << op << " of " << r.field("bytes")
              << " bytes from npm server: " << r.field("bytes_per_s") << " bytes/s\n";
    return r;
  }
  /// Waits for the server's report of a completed download of 1F50h/1.
  static void expect_stored(size_t bytes) {
    std::string line;
    ASSERT_TRUE(server_->wait_prefix("stored index=1F50 sub=1 ", kPeerDeadline, &line));
    EXPECT_EQ(field_of(line, "bytes"), std::to_string(bytes)) << line;
  }

  static TempDir* dir_;
  static LineChild* server_;
};
TempDir* NpmClientVsNpmServer::dir_ = nullptr;
LineChild* NpmClientVsNpmServer::server_ = nullptr;

TEST_F(NpmClientVsNpmServer, ExpeditedAndSegmentedSmallEntries) {
  PeerResult r = run_peer_client(args("upload", "0x2001", 0));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.field("transfer"), "expedited");
  EXPECT_EQ(r.field("data"), "78563412");

  r = run_peer_client(args("upload", "0x1008", 0));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.field("transfer"), "segmented");
  EXPECT_EQ(r.field("data"), to_hex(std::vector<uint8_t>{'n', 'p', 'm', ' ', 'c', 'a', 'n', 'o', 'p', 'e',
                                                         'n', ' ', 'p', 'e', 'e', 'r'}));

  const std::vector<uint8_t> text{'w', 'r', 'i', 't', 't', 'e', 'n', '!'};
  std::vector<std::string> a = args("download", "0x2002", 0);
  a.insert(a.end(), {"--data", to_hex(text)});
  r = run_peer_client(a);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.field("transfer"), "segmented");
  r = run_peer_client(args("upload", "0x2002", 0));
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.field("data"), to_hex(text));

  r = run_peer_client(args("upload", "0x3000", 0));
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_EQ(r.abort_code(), 0x06020000u) << r.describe();  // object does not exist
}

TEST_F(NpmClientVsNpmServer, BlockAndSegmentedUploadOf64KiB) {
  const std::vector<uint8_t> want = peer_pattern(kBig);
  for (bool block : {true, false}) {
    SCOPED_TRACE(block ? "block" : "segmented");
    const std::string file = dir_->path("up.bin");
    const PeerResult r = big("upload", block, file);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_EQ(r.field("transfer"), block ? "block" : "segmented");
    EXPECT_EQ(r.field("bytes"), std::to_string(kBig));
    EXPECT_TRUE(read_file(file) == want) << "not the server's pattern";
  }
}

TEST_F(NpmClientVsNpmServer, BlockAndSegmentedDownloadOf64KiBIsReadBack) {
  uint32_t seed = 1;
  for (bool block : {true, false}) {
    SCOPED_TRACE(block ? "block" : "segmented");
    const std::vector<uint8_t> content = other_content(kBig, seed++);
    const std::string file = dir_->path("down.bin");
    ASSERT_TRUE(write_file(file, content));
    const PeerResult w = big("download", block, file);
    ASSERT_EQ(w.exit_code, 0) << w.describe();
    EXPECT_EQ(w.field("transfer"), block ? "block" : "segmented");
    expect_stored(kBig);

    const std::string back = dir_->path("back.bin");
    const PeerResult r = big("upload", true, back);
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_TRUE(read_file(back) == content) << "the read-back differs from what was downloaded";
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co
