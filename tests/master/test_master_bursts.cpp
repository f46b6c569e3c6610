// mb2co-master's batched I/O (issue 25 item 6) against a block server and
// client written in this test from CiA 301 §7.2.4.3 (RogueServer: node 5 on
// vcan0, a thread of the test), not the project's SDO code: frames reach
// the master in bursts (a whole sub-block in one sendmmsg, more than one
// receive batch) and leave it in bursts (a block download's sub-block,
// queued and flushed together). Each transfer is checked byte for byte and
// by the CRC-16 this test computes; every sub-block must be acknowledged
// whole (a frame lost or reordered by the batching shows as a short ack,
// an out-of-sequence segment or a different byte).
// ctest master.bursts runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "master_cli.h"
#include "rogue_server.h"

namespace mb2co {
namespace test {
namespace {

constexpr unsigned kSegmentBytes = 7;
constexpr unsigned kBlockSize = 127;  ///< what the master offers and the server asks for
/// 1000 whole sub-blocks and a last one of 64 segments (two full receive
/// batches of 32: the master must find the socket empty by itself), the
/// last segment carrying 4 of its 7 bytes.
constexpr size_t kUploadBytes = kBlockSize * kSegmentBytes * 1000 + 64 * kSegmentBytes - 3;
/// A download of 300 sub-blocks and a part, sent by the master in bursts.
constexpr size_t kDownloadBytes = kBlockSize * kSegmentBytes * 300 + 50 * kSegmentBytes - 5;

/// CRC-16 of CiA 301 §7.2.4.3.16 (polynomial x^16 + x^12 + x^5 + 1,
/// initial value 0, no reflection), bit by bit from the definition.
uint16_t cia301_crc(const std::vector<uint8_t>& bytes) {
  uint16_t crc = 0;
  for (uint8_t b : bytes) {
    crc = static_cast<uint16_t>(crc ^ (b << 8));
    for (int i = 0; i < 8; ++i) crc = static_cast<uint16_t>((crc & 0x8000) ? (crc << 1) ^ 0x1021 : crc << 1);
  }
  return crc;
}

std::vector<uint8_t> content(size_t n, unsigned seed) {
  std::vector<uint8_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(i * seed + (i >> 9) * 7 + 1);
  return v;
}

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// A block upload server for one object (CiA 301 block upload, server
/// side): each sub-block goes out in one burst, every ack must be whole.
class UploadServer {
 public:
  explicit UploadServer(std::vector<uint8_t> object) : object_(std::move(object)) {}

  void on_request(RogueServer& s, const CanFrame& q) {
    const uint8_t cmd = q.data[0];
    if (cmd == 0xA4) {  // initiate: ccs 5, cc = 1, cs 0; blksize in byte 4
      asked_block_size_ = q.data[4];
      s.send(mux(q, 0xC6, static_cast<uint32_t>(object_.size())));  // CRC, size indicated
    } else if (cmd == 0xA3) {                                       // start
      send_sub_block(s, asked_block_size_);
    } else if (cmd == 0xA2) {  // ack: ackseq, next blksize
      const unsigned ackseq = q.data[1];
      if (ackseq != sent_in_sub_block_) ++short_acks_;
      offset_ = std::min(object_.size(), offset_ + static_cast<size_t>(ackseq) * kSegmentBytes);
      ++acks_;
      if (offset_ < object_.size()) return send_sub_block(s, q.data[2]);
      const size_t last = object_.size() % kSegmentBytes;
      const unsigned unused = last == 0 ? 0 : static_cast<unsigned>(kSegmentBytes - last);
      const uint16_t crc = cia301_crc(object_);
      s.send(Bytes8{static_cast<uint8_t>(0xC1 | (unused << 2)), static_cast<uint8_t>(crc & 0xFF),
                    static_cast<uint8_t>(crc >> 8), 0, 0, 0, 0, 0});
    } else if (cmd == 0xA1) {  // the client's end
      ended_ = true;
    } else {
      ++unexpected_;
    }
  }

  uint8_t asked_block_size_ = 0;
  unsigned acks_ = 0;
  unsigned short_acks_ = 0;
  unsigned unexpected_ = 0;
  bool ended_ = false;

 private:
  void send_sub_block(RogueServer& s, unsigned block_size) {
    std::vector<Bytes8> burst;
    size_t at = offset_;
    for (unsigned seq = 1; seq <= block_size && at < object_.size(); ++seq) {
      Bytes8 f{};
      const size_t n = std::min<size_t>(kSegmentBytes, object_.size() - at);
      const bool last = at + n == object_.size();
      f[0] = static_cast<uint8_t>(seq | (last ? 0x80 : 0));
      std::copy(object_.begin() + static_cast<long>(at), object_.begin() + static_cast<long>(at + n),
                f.begin() + 1);
      burst.push_back(f);
      at += n;
    }
    sent_in_sub_block_ = static_cast<unsigned>(burst.size());
    s.send(burst);  // one sendmmsg: the master reads it in batches
  }

  std::vector<uint8_t> object_;
  size_t offset_ = 0;
  unsigned sent_in_sub_block_ = 0;
};

/// A block download server (CiA 301 block download, server side): takes the
/// master's sub-blocks, acknowledges each when its last segment came.
class DownloadServer {
 public:
  void on_request(RogueServer& s, const CanFrame& q) {
    const uint8_t cmd = q.data[0];
    if (!initiated_) {
      if ((cmd & 0xE0) != 0xC0) return note_unexpected();
      initiated_ = true;
      size_ = q.data[4] | (q.data[5] << 8) | (q.data[6] << 16) | (static_cast<uint32_t>(q.data[7]) << 24);
      return s.send(mux(q, 0xA4, kBlockSize));  // CRC, blksize 127
    }
    if (in_sub_block_) {
      const unsigned seq = cmd & 0x7F;
      if (seq != expected_seq_) {
        ++out_of_sequence_;
      } else {
        segment_.assign(q.data + 1, q.data + 8);
        data_.insert(data_.end(), segment_.begin(), segment_.end());
        ++expected_seq_;
      }
      const bool last = (cmd & 0x80) != 0;
      if (last) in_sub_block_ = false;
      if (seq == kBlockSize || last) {
        s.send(Bytes8{0xA2, static_cast<uint8_t>(expected_seq_ - 1), kBlockSize, 0, 0, 0, 0, 0});
        expected_seq_ = 1;
        ++sub_blocks_;
      }
      return;
    }
    // The end: ccs 6, n unused bytes of the last segment, cs 1; CRC.
    if ((cmd & 0xE3) != 0xC1) return note_unexpected();
    const unsigned unused = (cmd >> 2) & 0x07;
    data_.resize(data_.size() - unused);
    crc_ = static_cast<uint16_t>(q.data[1] | (q.data[2] << 8));
    ended_ = true;
    s.send(Bytes8{0xA1, 0, 0, 0, 0, 0, 0, 0});
  }

  uint32_t size_ = 0;
  std::vector<uint8_t> data_;
  uint16_t crc_ = 0;
  unsigned sub_blocks_ = 0;
  unsigned out_of_sequence_ = 0;
  unsigned unexpected_ = 0;
  bool ended_ = false;

 private:
  void note_unexpected() { ++unexpected_; }

  bool initiated_ = false;
  bool in_sub_block_ = true;
  unsigned expected_seq_ = 1;
  std::vector<uint8_t> segment_;
};

class MasterBursts : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/mb2co_bursts_XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const char* name) const { return dir_ + "/" + name; }

  std::string dir_;
};

TEST_F(MasterBursts, BlockUploadOfWholeSubBlockBurstsIsByteForByteTheObject) {
  const std::vector<uint8_t> object = content(kUploadBytes, 13);
  UploadServer server(object);
  RogueServer rogue;
  ASSERT_TRUE(rogue.start([&](RogueServer& s, const CanFrame& q) { server.on_request(s, q); }))
      << rogue.error();
  const std::string file = path("up.bin");
  const MasterRun r = run_master({"-t", "5000", "upload", "5", "1F50", "1", file, "--block"});
  rogue.stop();
  ASSERT_EQ(r.exit_code, 0) << r.text() << r.err;
  EXPECT_NE(r.text().find("uploaded " + std::to_string(kUploadBytes) + " bytes"), std::string::npos)
      << r.text();
  EXPECT_NE(r.text().find("block with CRC"), std::string::npos) << r.text();
  EXPECT_EQ(server.asked_block_size_, kBlockSize);
  EXPECT_EQ(server.acks_, 1001u);  // every sub-block acknowledged once
  EXPECT_EQ(server.short_acks_, 0u) << "the master acknowledged less than a burst carried";
  EXPECT_EQ(server.unexpected_, 0u);
  EXPECT_TRUE(server.ended_) << "no end response (A1h) from the master";
  const std::vector<uint8_t> got = read_bytes(file);
  ASSERT_EQ(got.size(), object.size());
  EXPECT_TRUE(got == object) << "the uploaded file is not the server's object";
}

TEST_F(MasterBursts, BlockDownloadSentInBurstsIsByteForByteTheFile) {
  const std::vector<uint8_t> object = content(kDownloadBytes, 29);
  const std::string file = path("down.bin");
  {
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(object.data()), static_cast<std::streamsize>(object.size()));
  }
  DownloadServer server;
  RogueServer rogue;
  ASSERT_TRUE(rogue.start([&](RogueServer& s, const CanFrame& q) { server.on_request(s, q); }))
      << rogue.error();
  const MasterRun r = run_master({"-t", "5000", "download", "5", "1F50", "1", file, "--block"});
  rogue.stop();
  ASSERT_EQ(r.exit_code, 0) << r.text() << r.err;
  EXPECT_EQ(server.size_, kDownloadBytes);
  EXPECT_EQ(server.out_of_sequence_, 0u) << "segments out of order or lost in the master's bursts";
  EXPECT_EQ(server.unexpected_, 0u);
  EXPECT_EQ(server.sub_blocks_, 301u);
  ASSERT_TRUE(server.ended_) << "no end frame from the master";
  EXPECT_EQ(server.crc_, cia301_crc(object)) << "the master's CRC";
  ASSERT_EQ(server.data_.size(), object.size());
  EXPECT_TRUE(server.data_ == object) << "the server stored other bytes than the file";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
