// mb2co-master's SDO client against npm's canopen SDO server on vcan0 (ctest
// peers.master_vs_npm_server, inside hil/uml/run-with-vcan.sh): expedited
// and segmented reads and writes of its small entries, block (with CRC) and
// segmented uploads and downloads of 64 KiB of its 1F50h/1. What a download
// stored is read back by npm's own client (not ours), so our client and our
// reading of CiA 301 do not judge themselves.
#include <gtest/gtest.h>

#include <iostream>

#include "master_cli.h"
#include "node_harness.h"
#include "npm_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kServerNode = 0x22;
const std::string kNode = std::to_string(kServerNode);
/// 64 KiB: the last segment carries 2 of its 7 bytes (65536 = 9362 * 7 + 2).
constexpr size_t kBig = 64 * 1024;
/// Our client's SDO timeout: npm's server under user-mode Linux is slow.
const std::vector<std::string> kTimeout = {"-t", "5000"};

/// mb2co-master -i vcan0 -t 5000 ARGS.
MasterRun master(std::vector<std::string> args) {
  args.insert(args.begin(), kTimeout.begin(), kTimeout.end());
  return run_master(args, kPeerDeadline);
}

std::string describe(const MasterRun& r) {
  return "exit " + std::to_string(r.exit_code) + "\nstdout:\n" + r.text() + "stderr:\n" + r.err;
}

class MasterVsNpmServer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    server_ = new LineChild();
    ASSERT_TRUE(server_->start(peer_command({"server", "--node", kNode, "--size", std::to_string(kBig)})))
        << server_->error();
    ASSERT_TRUE(server_->wait_prefix("ready node=", kPeerDeadline)) << server_->stderr_text();
  }
  static void TearDownTestSuite() {
    delete server_;  // kills and reaps it
    delete dir_;
    server_ = nullptr;
    dir_ = nullptr;
  }
  /// Waits for the server's report of a completed download of INDEX/SUB
  /// ("stored index=2001 sub=0 bytes=4") and checks its size.
  static void expect_stored(const std::string& index, int sub, size_t bytes) {
    std::string line;
    ASSERT_TRUE(server_->wait_prefix("stored index=" + index + " sub=" + std::to_string(sub) + " ",
                                     kPeerDeadline, &line))
        << server_->stderr_text();
    EXPECT_EQ(field_of(line, "bytes"), std::to_string(bytes)) << line;
  }
  /// What the server holds in 1F50h/1, read by npm's own client (block).
  static std::vector<uint8_t> npm_reads_domain() {
    const std::string file = dir_->path("npm_read.bin");
    const PeerResult r = run_peer_client({"upload", "--node", kNode, "--index", "0x1F50", "--sub", "1",
                                          "--block", "--file", file, "--timeout", "5000"});
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    return read_file(file);
  }
  /// One 64 KiB transfer of 1F50h/1 by our client; its summary line.
  static std::string big(const char* op, const char* mode, const std::string& file) {
    const MasterRun r = master({op, kNode, "1F50", "1", file, mode});
    EXPECT_EQ(r.exit_code, 0) << describe(r);
    EXPECT_EQ(r.out.size(), 1u) << describe(r);
    std::cout << "mb2co-master vs npm server: " << (r.out.empty() ? "" : r.out[0]) << "\n";
    return r.out.empty() ? std::string() : r.out[0];
  }

  static TempDir* dir_;
  static LineChild* server_;
};
TempDir* MasterVsNpmServer::dir_ = nullptr;
LineChild* MasterVsNpmServer::server_ = nullptr;

TEST_F(MasterVsNpmServer, ExpeditedReadAndWriteOfAnUnsigned32) {
  MasterRun r = master({"read", kNode, "2001", "0", "u32"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.text(), "0x12345678\n");

  r = master({"write", kNode, "2001", "0", "u32", "0xCAFE0042"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.text(), "node 34 2001h/0: 4 bytes written\n");
  expect_stored("2001", 0, 4);

  r = master({"read", kNode, "2001", "0", "u32"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.text(), "0xCAFE0042\n");
  // npm's own client sees the same four bytes (little-endian).
  const PeerResult p = run_peer_client({"upload", "--node", kNode, "--index", "0x2001", "--sub", "0"});
  ASSERT_EQ(p.exit_code, 0) << p.describe();
  EXPECT_EQ(p.field("transfer"), "expedited") << p.describe();
  EXPECT_EQ(p.field("data"), "4200feca") << p.describe();
}

TEST_F(MasterVsNpmServer, ExpeditedAndSegmentedStrings) {
  // 1008h: 16 bytes, so the server answers segmented.
  MasterRun r = master({"read", kNode, "1008", "0", "vs"});
  ASSERT_EQ(r.exit_code, 0) << describe(r);
  EXPECT_EQ(r.text(), "npm canopen peer\n");

  // 4 bytes go expedited, 11 segmented; npm's client reads each back.
  for (const std::string text : {"abcd", "by mb2co 11"}) {
    SCOPED_TRACE(text);
    r = master({"write", kNode, "2002", "0", "vs", text});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    expect_stored("2002", 0, text.size());
    const PeerResult p = run_peer_client({"upload", "--node", kNode, "--index", "0x2002", "--sub", "0"});
    ASSERT_EQ(p.exit_code, 0) << p.describe();
    EXPECT_EQ(p.field("data"), to_hex(std::vector<uint8_t>(text.begin(), text.end()))) << p.describe();
    r = master({"read", kNode, "2002", "0", "vs"});
    ASSERT_EQ(r.exit_code, 0) << describe(r);
    EXPECT_EQ(r.text(), text + "\n");
  }
}

TEST_F(MasterVsNpmServer, RefusalsCarryNpmsAbortCode) {
  const MasterRun r = master({"read", kNode, "3000", "0", "u32"});
  EXPECT_EQ(r.exit_code, 1) << describe(r);                             // refused (SDO abort)
  EXPECT_NE(r.err.find("06020000"), std::string::npos) << describe(r);  // object does not exist
}

// configure all or nothing against a node that is not ours: the DCF (made
// for another device) sets 2001h and 2002h, which npm's server takes, then
// 2003h, which it does not have. Both are written back, in reverse order,
// and npm's own client reads the values they had.
TEST_F(MasterVsNpmServer, ConfigureRefusedHalfwayRestoresWhatItWrote) {
  auto npm_reads = [](const char* index) {
    const PeerResult p = run_peer_client({"upload", "--node", kNode, "--index", index, "--sub", "0"});
    EXPECT_EQ(p.exit_code, 0) << p.describe();
    return p.field("data");
  };
  const std::string u32_before = npm_reads("0x2001"), string_before = npm_reads("0x2002");
  const std::string var = "ObjectType=0x7\nAccessType=rw\nPDOMapping=0\n";
  ASSERT_TRUE(write_file(dir_->path("other.dcf"), [&] {
    const std::string t =
        "[FileInfo]\nFileName=other.dcf\nEDSVersion=4.0\n"
        "[DeviceInfo]\nVendorName=another\n"
        "[DeviceComissioning]\nNodeID=34\n"
        "[MandatoryObjects]\nSupportedObjects=0\n"
        "[ManufacturerObjects]\nSupportedObjects=3\n1=0x2001\n2=0x2002\n3=0x2003\n"
        "[2001]\nParameterName=a\nDataType=0x0007\n" +
        var + "ParameterValue=0x0BADCAFE\n" + "[2002]\nParameterName=b\nDataType=0x0009\n" + var +
        "ParameterValue=configured\n" + "[2003]\nParameterName=c\nDataType=0x0005\n" + var +
        "ParameterValue=1\n";
    return std::vector<uint8_t>(t.begin(), t.end());
  }()));
  const std::string net = "[Topology]\nNodes=1\nNode34Present=1\nNode34DCFName=other.dcf\n";
  ASSERT_TRUE(write_file(dir_->path("net.cpj"), std::vector<uint8_t>(net.begin(), net.end())));

  const MasterRun r = master({"configure", dir_->path("net.cpj"), "--no-start"});
  EXPECT_EQ(r.exit_code, 1) << describe(r);
  ASSERT_EQ(r.out.size(), 3u) << describe(r);
  EXPECT_EQ(r.out[0],
            "node 34: refused: writing 2003h/0: SDO abort 06020000h (object does not exist in the object "
            "dictionary)");
  EXPECT_EQ(r.out[1].rfind("node 34: restored 2002h/0 = ", 0), 0u) << r.out[1];
  EXPECT_EQ(r.out[2].rfind("node 34: restored 2001h/0 = 0x", 0), 0u) << r.out[2];
  EXPECT_EQ(npm_reads("0x2001"), u32_before);
  EXPECT_EQ(npm_reads("0x2002"), string_before);
}

TEST_F(MasterVsNpmServer, BlockAndSegmentedUploadOf64KiB) {
  // Before any download: the server's pattern.
  const std::vector<uint8_t> want = peer_pattern(kBig);
  const std::string file = dir_->path("up.bin");
  std::string line = big("upload", "--block", file);
  EXPECT_NE(line.find("uploaded 65536 bytes from node 34 1F50h/1"), std::string::npos) << line;
  EXPECT_NE(line.find("block with CRC"), std::string::npos) << line;
  EXPECT_TRUE(read_file(file) == want) << "block upload: not the server's pattern";

  line = big("upload", "--segmented", file);
  EXPECT_NE(line.find("uploaded 65536 bytes"), std::string::npos) << line;
  EXPECT_NE(line.find("expedited/segmented"), std::string::npos) << line;
  EXPECT_TRUE(read_file(file) == want) << "segmented upload: not the server's pattern";
}

TEST_F(MasterVsNpmServer, BlockAndSegmentedDownloadOf64KiBIsWhatNpmStored) {
  uint32_t seed = 0x1F50;
  for (const char* mode : {"--block", "--segmented"}) {
    SCOPED_TRACE(mode);
    const std::vector<uint8_t> content = other_content(kBig, seed++);
    const std::string file = dir_->path("down.bin");
    ASSERT_TRUE(write_file(file, content));
    const std::string line = big("download", mode, file);
    EXPECT_NE(line.find("downloaded 65536 bytes to node 34 1F50h/1"), std::string::npos) << line;
    expect_stored("1F50", 1, kBig);
    EXPECT_TRUE(npm_reads_domain() == content) << "npm's server holds other bytes than we downloaded";
    // And our block upload returns them too.
    const std::string back = dir_->path("back.bin");
    big("upload", "--block", back);
    EXPECT_TRUE(read_file(back) == content) << "our read-back differs from what we downloaded";
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co
