// npm's canopen SDO client against mb2co-node's SDO server on vcan0 (ctest
// peers.npm_client_vs_node runs this binary inside hil/uml/run-with-vcan.sh).
// The expected values come from the published EDS (docs/mb2co-gateway.eds),
// and the transfer kind from the server's first answer as the peer saw it.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <iostream>
#include <map>
#include <utility>

#include "node_harness.h"
#include "npm_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr int kNodeId = 5;

std::string hex4(unsigned v) {
  char s[8];
  snprintf(s, sizeof s, "0x%04X", v);
  return s;
}

/// Client arguments for one transfer with node kNodeId.
std::vector<std::string> transfer_args(const char* op, uint16_t index, uint8_t sub) {
  return {op, "--node", std::to_string(kNodeId), "--index", hex4(index), "--sub", std::to_string(sub)};
}

/// `value` as the little-endian bytes of an object of `size` bytes.
std::vector<uint8_t> le_bytes(unsigned long value, size_t size) {
  std::vector<uint8_t> b;
  for (size_t i = 0; i < size; ++i) b.push_back(static_cast<uint8_t>(value >> (8 * i)));
  return b;
}

std::vector<uint8_t> text_bytes(const std::string& s) {
  return std::vector<uint8_t>(s.begin(), s.end());
}

class NpmClientVsNode : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    node_ = new NodeProcess();
    // The node answers SDO from pre-operational on, which it reaches before
    // its ready line (it enters operational by itself, 2000h/8 = 1).
    ASSERT_TRUE(node_->start(
        {"--can", "vcan0", "--node-id", std::to_string(kNodeId), "--pty", dir_->path("pty")}, kPeerDeadline))
        << node_->error();
  }
  static void TearDownTestSuite() {
    if (node_ != nullptr) {
      EXPECT_EQ(node_->stop(), 0) << node_->child.stderr_text();
    }
    delete node_;
    delete dir_;
    node_ = nullptr;
    dir_ = nullptr;
  }
  /// Uploads and expects success with this transfer kind and these bytes.
  static void expect_upload(uint16_t index, uint8_t sub, const char* transfer,
                            const std::vector<uint8_t>& want) {
    const PeerResult r = run_peer_client(transfer_args("upload", index, sub));
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_EQ(r.field("transfer"), transfer) << r.describe();
    EXPECT_EQ(r.field("bytes"), std::to_string(want.size())) << r.describe();
    EXPECT_EQ(r.field("data"), to_hex(want)) << r.describe();
  }

  static TempDir* dir_;
  static NodeProcess* node_;
};
TempDir* NpmClientVsNode::dir_ = nullptr;
NodeProcess* NpmClientVsNode::node_ = nullptr;

const char* eds() {
  return MB2CO_GATEWAY_EDS;
}
unsigned long eds_number(uint16_t index, uint8_t sub) {
  return strtoul(eds_default(eds(), index, sub).c_str(), nullptr, 0);
}

TEST_F(NpmClientVsNode, SegmentedUploadOfTheDeviceStrings) {
  for (uint16_t index : {uint16_t{0x1008}, uint16_t{0x1009}, uint16_t{0x100A}}) {
    SCOPED_TRACE(hex4(index));
    const std::string text = eds_default(eds(), index, 0);
    ASSERT_GT(text.size(), 4u) << "a string the EDS gives that only a segmented transfer can carry";
    expect_upload(index, 0, "segmented", text_bytes(text));
  }
}

TEST_F(NpmClientVsNode, ExpeditedUploadOfNumbers) {
  expect_upload(0x1017, 0, "expedited", le_bytes(eds_number(0x1017, 0), 2));
  for (uint8_t sub : {uint8_t{1}, uint8_t{2}, uint8_t{3}})
    expect_upload(0x1018, sub, "expedited", le_bytes(eds_number(0x1018, sub), 4));
  expect_upload(0x2000, 6, "expedited", le_bytes(eds_number(0x2000, 6), 2));
}

TEST_F(NpmClientVsNode, ExpeditedDownloadIsReadBack) {
  // 2000h/6 (button debounce, U16 rw) to 35 ms and back to its default.
  const unsigned long initial = eds_number(0x2000, 6);
  for (unsigned long value : {35ul, initial}) {
    std::vector<std::string> args = transfer_args("download", 0x2000, 6);
    args.insert(args.end(), {"--data", to_hex(le_bytes(value, 2))});
    const PeerResult w = run_peer_client(args);
    ASSERT_EQ(w.exit_code, 0) << w.describe();
    EXPECT_EQ(w.field("transfer"), "expedited") << w.describe();
    expect_upload(0x2000, 6, "expedited", le_bytes(value, 2));
  }
}

TEST_F(NpmClientVsNode, SegmentedDownloadsAreRefusedWithTheCiA301Codes) {
  // npm's client goes segmented above 4 bytes; apart from the DOMAIN 1F50h/1
  // the node's writable entries have <= 4 bytes, so it meets a refusal: the
  // write-protected device name, and too many bytes for a U16.
  struct Case {
    uint16_t index;
    uint8_t sub;
    std::vector<uint8_t> data;
    uint32_t abort;
  };
  const Case cases[] = {
      {0x1008, 0, text_bytes("a new name"), 0x06010002u},  // read-only object
      {0x2000, 6, le_bytes(0x12345678, 6), 0x06070012u},   // length too high
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(hex4(c.index));
    std::vector<std::string> args = transfer_args("download", c.index, c.sub);
    args.insert(args.end(), {"--data", to_hex(c.data)});
    const PeerResult r = run_peer_client(args);
    EXPECT_EQ(r.exit_code, 1) << r.describe();
    EXPECT_EQ(r.abort_code(), c.abort) << r.describe();
  }
  expect_upload(0x2000, 6, "expedited", le_bytes(eds_number(0x2000, 6), 2));
}

// Block transfers of npm's client (always with CRC) against the node, in this
// order. `abort` 0 means the transfer must succeed: a download writes
// other_content(bytes) and a later upload of the same object must return
// exactly what was written (an upload needs an earlier download in the table).
struct BlockCase {
  const char* op;  ///< "upload" or "download"
  uint16_t index;
  uint8_t sub;
  size_t bytes;    ///< download: how many; upload: expected size
  uint32_t abort;  ///< expected SDO abort code, 0 for success
};
const BlockCase kBlockCases[] = {
    // 1F50h/1 (DOMAIN, up to 1 MiB, block transfer with CRC): 64 KiB written
    // by a block download, then read back by a block upload. npm's client
    // checks the CRC the node sends at the end of the upload, the node the
    // one npm sends at the end of the download.
    {"download", 0x1F50, 1, 65536, 0},
    {"upload", 0x1F50, 1, 65536, 0},
};

TEST_F(NpmClientVsNode, BlockTransfers) {
  std::map<std::pair<uint16_t, uint8_t>, std::vector<uint8_t>> written;
  for (const BlockCase& c : kBlockCases) {
    SCOPED_TRACE(std::string(c.op) + " " + hex4(c.index) + "/" + std::to_string(c.sub));
    const std::string file = dir_->path("block.bin");
    std::vector<std::string> args = transfer_args(c.op, c.index, c.sub);
    args.insert(args.end(), {"--block", "--file", file, "--timeout", "5000"});
    const bool download = std::string(c.op) == "download";
    const std::vector<uint8_t> content = other_content(c.bytes, c.index * 256u + c.sub);
    if (download) {
      ASSERT_TRUE(write_file(file, content));
    }
    const PeerResult r = run_peer_client(args);
    if (c.abort != 0) {
      EXPECT_EQ(r.exit_code, 1) << r.describe();
      EXPECT_EQ(r.abort_code(), c.abort) << r.describe();
      // npm's client did ask for a block transfer (the server refuses an
      // upload in its first answer, so no protocol was chosen there).
      EXPECT_EQ(r.field("transfer"), download ? "block" : "none") << r.describe();
      continue;
    }
    ASSERT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_EQ(r.field("transfer"), "block") << r.describe();
    EXPECT_EQ(r.field("bytes"), std::to_string(c.bytes)) << r.describe();
    std::cout << "npm client block " << c.op << " of " << c.bytes
              << " bytes from mb2co-node: " << r.field("bytes_per_s") << " bytes/s\n";
    const auto key = std::make_pair(c.index, c.sub);
    if (download) {
      written[key] = content;
    } else {
      ASSERT_EQ(written.count(key), 1u) << "an upload case without an earlier download";
      EXPECT_TRUE(read_file(file) == written[key])
          << "the upload returned other bytes than the download wrote";
    }
  }
}

TEST_F(NpmClientVsNode, SegmentedDownloadOf64KiBIsReadBackSegmented) {
  // npm's client without --block: a segmented download of 64 KiB (9363
  // segments, each acknowledged, the toggle bit alternating), then a
  // segmented upload must return the same bytes.
  const size_t bytes = 65536;
  const std::vector<uint8_t> content = other_content(bytes, 0x51F50);
  const std::string file = dir_->path("segmented.bin");
  ASSERT_TRUE(write_file(file, content));
  std::vector<std::string> args = transfer_args("download", 0x1F50, 1);
  args.insert(args.end(), {"--file", file, "--timeout", "5000"});
  const PeerResult w = run_peer_client(args);
  ASSERT_EQ(w.exit_code, 0) << w.describe();
  EXPECT_EQ(w.field("transfer"), "segmented") << w.describe();
  EXPECT_EQ(w.field("bytes"), std::to_string(bytes)) << w.describe();

  const std::string back = dir_->path("segmented_back.bin");
  args = transfer_args("upload", 0x1F50, 1);
  args.insert(args.end(), {"--file", back, "--timeout", "5000"});
  const PeerResult r = run_peer_client(args);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.field("transfer"), "segmented") << r.describe();
  EXPECT_EQ(r.field("bytes"), std::to_string(bytes)) << r.describe();
  EXPECT_TRUE(read_file(back) == content)
      << "the segmented upload returned other bytes than the download wrote";
  std::cout << "npm client segmented download/upload of " << bytes
            << " bytes with mb2co-node: " << w.field("bytes_per_s") << " / " << r.field("bytes_per_s")
            << " bytes/s\n";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
