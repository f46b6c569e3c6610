// An SDO block download to mb2co-node's 1F50h/1 written frame by frame from
// the CiA 301 byte layout (§7.2.4.3.9-12) with can-utils (ctest
// peers.block_by_hand, inside hil/uml/run-with-vcan.sh): cansend plays the
// client, candump shows the server's answers. A segment is left out on
// purpose; the server's ack names the last segment it took in sequence, the
// client resends from there, and the end frame carries a CRC computed here
// from the CRC-16 definition of CiA 301 (not from shared/canopen). Then
// mb2co-master uploads the object and must get the same bytes. No code of
// ours runs on the client side of the exchange.
#include <gtest/gtest.h>

#include <cstdio>

#include "master_cli.h"
#include "node_harness.h"
#include "npm_peer.h"

namespace mb2co {
namespace test {
namespace {

constexpr unsigned kNodeId = 5;
constexpr unsigned kRequestId = 0x600 + kNodeId;   // client -> server (605h)
constexpr unsigned kResponseId = 0x580 + kNodeId;  // server -> client (585h)

/// CiA 301 §7.2.4.3.16: CRC-16 with the polynomial x^16 + x^12 + x^5 + 1
/// (1021h), initial value 0, bits taken most significant first, no final
/// XOR. Bit by bit, as the definition reads.
uint16_t ccitt_crc16(const std::vector<uint8_t>& bytes) {
  uint16_t crc = 0;
  for (uint8_t b : bytes) {
    for (int bit = 7; bit >= 0; --bit) {
      const bool in = ((b >> bit) & 1) != 0;
      const bool top = (crc & 0x8000) != 0;
      crc = static_cast<uint16_t>(crc << 1);
      if (in != top) crc ^= 0x1021;
    }
  }
  return crc;
}

/// "605#C6501F01..." for cansend.
std::string frame_text(unsigned id, const std::vector<uint8_t>& data) {
  char s[8];
  std::snprintf(s, sizeof s, "%03X#", id);
  std::string t = s;
  for (uint8_t b : data) {
    std::snprintf(s, sizeof s, "%02X", b);
    t += s;
  }
  return t;
}

class BlockByHand : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(node_.start(
        {"--can", "vcan0", "--node-id", std::to_string(kNodeId), "--pty", dir_.path("pty")}, kPeerDeadline))
        << node_.error();
    ASSERT_TRUE(start_candump(&candump_)) << candump_.error();
  }
  void TearDown() override { EXPECT_EQ(node_.stop(), 0) << node_.child.stderr_text(); }

  /// One frame from the client's side, by cansend.
  void send(const std::vector<uint8_t>& data) {
    ASSERT_EQ(data.size(), 8u) << "SDO frames are 8 bytes";
    LineChild cansend;
    ASSERT_TRUE(cansend.start({"cansend", "vcan0", frame_text(kRequestId, data)})) << cansend.error();
    ASSERT_EQ(cansend.wait_exit(kPeerDeadline), 0) << cansend.stderr_text();
  }
  /// The server's next frame (585h) as candump saw it; frames of other ids
  /// (the node's heartbeat, our own requests) are passed over. Empty when
  /// none came.
  std::vector<unsigned> next_answer() {
    std::string line;
    std::vector<unsigned> data;
    const auto is_answer = [&](const std::string& l) {
      unsigned id = 0;
      return parse_candump(l, &id, &data) && id == kResponseId;
    };
    if (!candump_.wait_line(is_answer, kPeerDeadline, &line)) return {};
    return data;
  }

  TempDir dir_;
  NodeProcess node_;
  LineChild candump_;
};

TEST_F(BlockByHand, LostSegmentIsResentFromTheAckAndTheBytesArriveWhole) {
  // 25 bytes: four segments of 7, 7, 7 and 4 data bytes (n = 3 unused).
  std::vector<uint8_t> content;
  for (unsigned i = 0; i < 25; ++i) content.push_back(static_cast<uint8_t>(0xA0 + 3 * i));
  const auto segment = [&](unsigned k) {  // data of segment k (0-based), padded with 0
    std::vector<uint8_t> d(7, 0);
    for (unsigned i = 0; i < 7 && 7 * k + i < content.size(); ++i) d[i] = content[7 * k + i];
    return d;
  };
  // A segment frame: byte 0 = c (bit 7, 1 on the object's last segment) |
  // seqno (bits 6..0, 1..127 within the sub-block); bytes 1..7 data.
  const auto segment_frame = [&](unsigned seqno, unsigned k) {
    std::vector<uint8_t> f{static_cast<uint8_t>((k == 3 ? 0x80 : 0x00) | seqno)};
    const std::vector<uint8_t> d = segment(k);
    f.insert(f.end(), d.begin(), d.end());
    return f;
  };

  // Initiate block download. Byte 0: ccs = 6 (bits 7..5 = 110), bits 4..3
  // reserved 0, cc = 1 (bit 2: the client does CRC), s = 1 (bit 1: size in
  // bytes 4..7), cs = 0 (bit 0: initiate) -> C6h. Bytes 1..2 index 1F50h
  // little-endian, byte 3 sub-index 1, bytes 4..7 size 25 little-endian.
  send({0xC6, 0x50, 0x1F, 0x01, 25, 0, 0, 0});
  // Answer: scs = 5 (101), reserved 00, sc (bit 2: the server does CRC),
  // ss = 0 (bits 1..0: initiate) -> A0h/A4h; index and sub echoed; byte 4
  // blksize: segments per sub-block (1..127).
  std::vector<unsigned> a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a[0] & ~0x04u, 0xA0u) << "not an initiate block download response";
  const bool server_crc = (a[0] & 0x04u) != 0;
  EXPECT_TRUE(server_crc) << "mb2co-node offers CRC";
  EXPECT_EQ(a[1], 0x50u);
  EXPECT_EQ(a[2], 0x1Fu);
  EXPECT_EQ(a[3], 0x01u);
  const unsigned blksize = a[4];
  ASSERT_GE(blksize, 4u) << "the plan below wants all four segments in one sub-block";
  ASSERT_LE(blksize, 127u);

  // Sub-block 1: seqno 1, then seqno 2 left out on purpose, then 3 and 4
  // (4 carries c = 1: the last segment of the object). The server takes
  // segments in sequence only, so 3 and 4 are dropped; c = 1 ends the
  // sub-block and makes it answer.
  send(segment_frame(1, 0));
  send(segment_frame(3, 2));
  send(segment_frame(4, 3));
  // Block ack: byte 0 = scs 5 | ss 2 -> A2h; byte 1 ackseq: the last seqno
  // received in sequence (1); byte 2 blksize of the next sub-block.
  a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a[0], 0xA2u) << "not a block ack (80h: an abort)";
  EXPECT_EQ(a[1], 1u) << "ackseq must name seqno 1, the last one in sequence";
  const unsigned blksize2 = a[2];
  ASSERT_GE(blksize2, 3u);

  // Sub-block 2 resends everything after ackseq, numbered from 1 again:
  // segments 2, 3, 4 of the object as seqno 1, 2, 3 (c = 1 on the last).
  send(segment_frame(1, 1));
  send(segment_frame(2, 2));
  send(segment_frame(3, 3));
  a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a[0], 0xA2u);
  EXPECT_EQ(a[1], 3u) << "all three resent segments in sequence";

  // End block download. Byte 0: ccs = 6 (110), n (bits 4..2) = 3 bytes of
  // the last segment without data, bit 1 reserved 0, cs = 1 (bit 0: end)
  // -> C0h | 3 << 2 | 1 = CDh. Bytes 1..2 the CRC of the 25 bytes,
  // little-endian; bytes 3..7 reserved 0.
  const uint16_t crc = ccitt_crc16(content);
  send({0xCD, static_cast<uint8_t>(crc & 0xFF), static_cast<uint8_t>(crc >> 8), 0, 0, 0, 0, 0});
  // Answer: scs = 5 | ss = 1 -> A1h (an abort 80h with 05040004h would say
  // the CRC differs).
  a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a[0], 0xA1u) << "not the end block download response";

  // mb2co-master reads the object back: exactly the 25 bytes.
  const std::string file = dir_.path("back.bin");
  const MasterRun up =
      run_master({"upload", std::to_string(kNodeId), "1F50", "1", file, "--block"}, kPeerDeadline);
  ASSERT_EQ(up.exit_code, 0) << up.text() << up.err;
  EXPECT_TRUE(read_file(file) == content) << "the upload returned other bytes than the hand-written download";
}

TEST_F(BlockByHand, WrongCrcIsRefusedWith05040004h) {
  // The same layout as above, one sub-block without loss: 3 bytes in one
  // segment (n = 4), and an end frame whose CRC is off by one.
  const std::vector<uint8_t> content{0x11, 0x22, 0x33};
  send({0xC6, 0x50, 0x1F, 0x01, 3, 0, 0, 0});
  std::vector<unsigned> a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  ASSERT_EQ(a[0] & ~0x04u, 0xA0u);
  send({0x81, 0x11, 0x22, 0x33, 0, 0, 0, 0});  // c = 1, seqno 1
  a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a[0], 0xA2u);
  EXPECT_EQ(a[1], 1u);
  const uint16_t bad = static_cast<uint16_t>(ccitt_crc16(content) + 1);
  send(
      {0xD1, static_cast<uint8_t>(bad & 0xFF), static_cast<uint8_t>(bad >> 8), 0, 0, 0, 0, 0});  // C0h|4<<2|1
  // Abort: 80h, index, sub, code 05040004h (CRC error) little-endian.
  a = next_answer();
  ASSERT_EQ(a.size(), 8u);
  EXPECT_EQ(a, (std::vector<unsigned>{0x80, 0x50, 0x1F, 0x01, 0x04, 0x00, 0x04, 0x05}));
  // The object kept its start content (131072 bytes of i mod 251).
  const std::string file = dir_.path("kept.bin");
  const MasterRun up =
      run_master({"upload", std::to_string(kNodeId), "1F50", "1", file, "--block"}, kPeerDeadline);
  ASSERT_EQ(up.exit_code, 0) << up.text() << up.err;
  const std::vector<uint8_t> kept = read_file(file);
  ASSERT_EQ(kept.size(), 131072u);
  for (size_t i = 0; i < kept.size(); ++i)
    if (kept[i] != i % 251) FAIL() << "byte " << i << " is " << unsigned(kept[i]);
}

TEST(Crc16, TheCheckValueOfCiA301sCrc) {
  // "123456789" -> 31C3h, the CRC-16/XMODEM check value of this definition.
  const std::string s = "123456789";
  EXPECT_EQ(ccitt_crc16(std::vector<uint8_t>(s.begin(), s.end())), 0x31C3u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
