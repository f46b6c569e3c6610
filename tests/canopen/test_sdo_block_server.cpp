// The SdoServer's block transfer (MB2CO_CONFIG_SDO_BLOCK) against a client
// scripted byte by byte from the CiA 301 layout (§7.2.4.3.9-16), so that a
// misreading shared by our SdoClient and SdoServer cannot hide: initiate,
// sub-blocks, the ack and resend from ackseq, the end phase with n and the
// CRC, the protocol switch, block size and sequence checks; and domain
// objects (sdo_domain.h) by plain transfers, keeping their old content when
// a download does not complete.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopen/sdo_block.h"
#include "canopen/sdo_server.h"
#include "ionode/io_node.h"
#include "sdo_crc_reference.h"
#include "test_fixture.h"
#include "test_sdo_client_link.h"

namespace mb2co {
namespace test {
namespace {

using Bytes = std::vector<uint8_t>;

// CRC-16/XMODEM written out independently of sdo_crc16 (byte-wise shifts of
// the whole 16-bit register), pinned by the check value of the CRC catalogue.
Bytes bytes(const std::string& s) {
  return Bytes(s.begin(), s.end());
}

TEST(SdoBlockCrc, MatchesTheCrcCatalogueCheckValueAndChains) {
  const Bytes check = bytes("123456789");
  EXPECT_EQ(crc_ref(check), 0x31C3);
  EXPECT_EQ(canopen::sdo_crc16(0, check.data(), 9), 0x31C3);
  const uint16_t first = canopen::sdo_crc16(0, check.data(), 4);
  EXPECT_EQ(canopen::sdo_crc16(first, check.data() + 4, 5), 0x31C3);
  const Bytes p = pattern(1000);
  EXPECT_EQ(canopen::sdo_crc16(0, p.data(), 1000), crc_ref(p));
}

class SdoBlockServer : public ::testing::Test {
 protected:
  void SetUp() override {
    io.start(3, 0);
    server.init(&io.od(), 3);
    table = domain.table();
    server.set_domain(&table);
    server.set_block_transfer(true);
  }

  /// A request on 603h (8 bytes, zeros after `b`); the server's answers, as strings.
  Frames req(std::initializer_list<uint8_t> b) {
    server.on_frame(frame(b), now, log.sink());
    return log.take();
  }
  static CanFrame frame(std::initializer_list<uint8_t> b) {
    CanFrame f = F(0x603, {0, 0, 0, 0, 0, 0, 0, 0});
    uint8_t i = 0;
    for (uint8_t x : b) f.data[i++] = x;
    return f;
  }
  /// A block segment: seqno | c, then 7 bytes of `data` from `offset` (zeros past its end).
  Frames seg(uint8_t seqno, bool last, const Bytes& data, size_t offset) {
    CanFrame f = F(0x603, {static_cast<uint8_t>(seqno | (last ? 0x80 : 0)), 0, 0, 0, 0, 0, 0, 0});
    for (size_t i = 0; i < 7 && offset + i < data.size(); ++i) f.data[1 + i] = data[offset + i];
    server.on_frame(f, now, log.sink());
    return log.take();
  }
  Frames end(uint8_t n, uint16_t crc) {
    return req({static_cast<uint8_t>(0xC1 | (n << 2)), static_cast<uint8_t>(crc),
                static_cast<uint8_t>(crc >> 8), 0, 0, 0, 0, 0});
  }
  std::string label() {
    uint8_t buf[32];
    const uint16_t n = io.od().copy_out(io.od().find(0x2000, 0), buf, sizeof buf);
    return std::string(buf, buf + n);
  }
  static std::string abort(uint16_t index, uint8_t sub, uint32_t code) {
    return abort_frame(3, index, sub, code);
  }

  FrameLog node_log;
  ionode::IoNode io{node_log.sink()};
  FrameLog log;
  canopen::SdoServer server{};
  RamDomain domain{0x1F50, 1, 4096};
  canopen::SdoDomain table{};
  uint32_t now = 0;
};

TEST_F(SdoBlockServer, DownloadOfAStringFrameByFrame) {
  const Bytes data = bytes("Hello block!");  // 12 bytes: 7 + 5, n = 2
  EXPECT_EQ(req({0xC6, 0x00, 0x20, 0x00, 12, 0, 0, 0}), Frames{"<583> A4 00 20 00 7F 00 00 00"});
  EXPECT_EQ(seg(1, false, data, 0), Frames{});  // no answer inside a sub-block
  EXPECT_EQ(seg(2, true, data, 7), Frames{"<583> A2 02 7F 00 00 00 00 00"});
  EXPECT_EQ(label(), "");  // nothing reaches the OD before the end phase
  const uint16_t crc = crc_ref(data);
  EXPECT_EQ(end(2, crc), Frames{"<583> A1 00 00 00 00 00 00 00"});
  EXPECT_EQ(label(), "Hello block!");
  EXPECT_FALSE(server.busy());
}

TEST_F(SdoBlockServer, DownloadAcksTheLastSegmentInSequenceAndTakesTheResend) {
  const Bytes data = bytes("ABCDEFGHIJKLMNOPQRST");  // 20 bytes: 7 + 7 + 6, n = 1
  EXPECT_EQ(req({0xC6, 0x00, 0x20, 0x00, 20, 0, 0, 0}), Frames{"<583> A4 00 20 00 7F 00 00 00"});
  EXPECT_EQ(seg(1, false, data, 0), Frames{});
  // Segment 2 is lost; 3 (the last) arrives: ackseq 1.
  EXPECT_EQ(seg(3, true, data, 14), Frames{"<583> A2 01 7F 00 00 00 00 00"});
  // The next sub-block starts after byte 7, from seqno 1.
  EXPECT_EQ(seg(1, false, data, 7), Frames{});
  EXPECT_EQ(seg(2, true, data, 14), Frames{"<583> A2 02 7F 00 00 00 00 00"});
  EXPECT_EQ(end(1, crc_ref(data)), Frames{"<583> A1 00 00 00 00 00 00 00"});
  EXPECT_EQ(label(), "ABCDEFGHIJKLMNOPQRST");
}

TEST_F(SdoBlockServer, DownloadWithAWrongCrcIsAbortedAndChangesNothing) {
  const Bytes data = bytes("twelve bytes");
  req({0xC6, 0x00, 0x20, 0x00, 12, 0, 0, 0});
  seg(1, false, data, 0);
  EXPECT_EQ(seg(2, true, data, 7), Frames{"<583> A2 02 7F 00 00 00 00 00"});
  EXPECT_EQ(end(2, static_cast<uint16_t>(crc_ref(data) ^ 0x0100)), Frames{abort(0x2000, 0, 0x05040004)});
  EXPECT_EQ(label(), "");
  EXPECT_FALSE(server.busy());
}

TEST_F(SdoBlockServer, DownloadWithoutClientCrcIgnoresTheCrcField) {
  const Bytes data = bytes("no crc");
  EXPECT_EQ(req({0xC2, 0x00, 0x20, 0x00, 6, 0, 0, 0}), Frames{"<583> A4 00 20 00 7F 00 00 00"});  // cc = 0
  EXPECT_EQ(seg(1, true, data, 0), Frames{"<583> A2 01 7F 00 00 00 00 00"});
  EXPECT_EQ(end(1, 0x0000), Frames{"<583> A1 00 00 00 00 00 00 00"});
  EXPECT_EQ(label(), "no crc");
}

TEST_F(SdoBlockServer, DownloadSizesAreChecked) {
  // Announced 12, 10 sent: the end phase finds the mismatch (06070010h).
  const Bytes ten = bytes("0123456789");
  req({0xC6, 0x00, 0x20, 0x00, 12, 0, 0, 0});
  seg(1, false, ten, 0);
  seg(2, true, ten, 7);
  EXPECT_EQ(end(4, crc_ref(ten)), Frames{abort(0x2000, 0, 0x06070010)});
  // More than the object holds (24 bytes), announced: refused at once.
  EXPECT_EQ(req({0xC6, 0x00, 0x20, 0x00, 30, 0, 0, 0}), Frames{abort(0x2000, 0, 0x06070012)});
  // ... and unannounced: refused when the 25th byte is known to be data.
  const Bytes long_data = pattern(35);
  EXPECT_EQ(req({0xC4, 0x00, 0x20, 0x00, 0, 0, 0, 0}), Frames{"<583> A4 00 20 00 7F 00 00 00"});
  for (uint8_t s = 1; s <= 4; ++s) EXPECT_EQ(seg(s, false, long_data, (s - 1u) * 7u), Frames{}) << int(s);
  EXPECT_EQ(seg(5, true, long_data, 28), Frames{abort(0x2000, 0, 0x06070012)});
  EXPECT_EQ(label(), "");
  // A read-only object: refused at the initiate, as a segmented download.
  EXPECT_EQ(req({0xC6, 0x08, 0x10, 0x00, 4, 0, 0, 0}), Frames{abort(0x1008, 0, 0x06010002)});
}

TEST_F(SdoBlockServer, UploadOfTheDeviceNameFrameByFrame) {
  const Bytes name = bytes("mb2co I/O node");  // 14 bytes: two full segments, n = 0
  EXPECT_EQ(req({0xA4, 0x08, 0x10, 0x00, 0x7F, 0x00, 0, 0}), Frames{"<583> C6 08 10 00 0E 00 00 00"});
  EXPECT_EQ(req({0xA3}), (Frames{"<583> 01 6D 62 32 63 6F 20 49", "<583> 82 2F 4F 20 6E 6F 64 65"}));
  const uint16_t crc = crc_ref(name);
  char end_frame[64];
  std::snprintf(end_frame, sizeof end_frame, "<583> C1 %02X %02X 00 00 00 00 00", crc & 0xFF, crc >> 8);
  EXPECT_EQ(req({0xA2, 0x02, 0x7F}), Frames{end_frame});
  EXPECT_TRUE(server.busy());
  EXPECT_EQ(req({0xA1}), Frames{});  // the client's end response closes it silently
  EXPECT_FALSE(server.busy());
}

TEST_F(SdoBlockServer, UploadResendsFromTheClientsAckseq) {
  req({0xA4, 0x08, 0x10, 0x00, 0x7F, 0x00, 0, 0});
  req({0xA3});
  // Only segment 1 arrived: the rest again, numbered from 1.
  EXPECT_EQ(req({0xA2, 0x01, 0x7F}), Frames{"<583> 81 2F 4F 20 6E 6F 64 65"});
  const Frames e = req({0xA2, 0x01, 0x7F});
  ASSERT_EQ(e.size(), 1u);
  const uint16_t crc = crc_ref(bytes("mb2co I/O node"));  // each byte counted once
  char end_frame[64];
  std::snprintf(end_frame, sizeof end_frame, "<583> C1 %02X %02X 00 00 00 00 00", crc & 0xFF, crc >> 8);
  EXPECT_EQ(e[0], end_frame);
}

TEST_F(SdoBlockServer, UploadSubBlocksHaveTheClientsSizeAndTheEndStatesUnusedBytes) {
  domain.content = pattern(50);  // 8 segments, the last with 1 byte: n = 6
  EXPECT_EQ(req({0xA4, 0x50, 0x1F, 0x01, 3, 0x00, 0, 0}), Frames{"<583> C6 50 1F 01 32 00 00 00"});
  Bytes got;
  std::vector<uint8_t> seqnos;
  auto collect = [&](std::initializer_list<uint8_t> b) {
    server.on_frame(frame(b), now, log.sink());
    std::vector<CanFrame> out = log.frames;
    log.frames.clear();
    for (const CanFrame& f : out) {
      seqnos.push_back(f.data[0]);
      if ((f.data[0] & 0xE3) != 0xC1)
        got.insert  // not the end frame
            (got.end(), &f.data[1], &f.data[8]);
    }
    return out;
  };
  EXPECT_EQ(collect({0xA3}).size(), 3u);
  EXPECT_EQ(collect({0xA2, 3, 2}).size(), 2u);  // the client shrinks the next sub-block to 2
  EXPECT_EQ(collect({0xA2, 2, 3}).size(), 3u);
  const std::vector<CanFrame> e = collect({0xA2, 3, 3});
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].data[0], 0xC1 | (6 << 2));
  const Bytes sent(got.begin(), got.begin() + 50);
  EXPECT_EQ(sent, domain.content);
  EXPECT_EQ(canopen::le16(&e[0].data[1]), crc_ref(domain.content));
  EXPECT_EQ(seqnos, (std::vector<uint8_t>{1, 2, 3, 1, 2, 1, 2, 0x83, 0xD9}));
}

TEST_F(SdoBlockServer, BlockSizeAndSequenceNumbersAreChecked) {
  EXPECT_EQ(req({0xA4, 0x08, 0x10, 0x00, 0, 0, 0, 0}), Frames{abort(0x1008, 0, 0x05040002)});
  EXPECT_EQ(req({0xA4, 0x08, 0x10, 0x00, 128, 0, 0, 0}), Frames{abort(0x1008, 0, 0x05040002)});
  req({0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0});
  req({0xA3});                                                            // 2 segments out
  EXPECT_EQ(req({0xA2, 3, 0x7F}), Frames{abort(0x1008, 0, 0x05040003)});  // acks a segment never sent
  req({0xA4, 0x08, 0x10, 0x00, 0x7F, 0, 0, 0});
  req({0xA3});
  EXPECT_EQ(req({0xA2, 1, 0}), Frames{abort(0x1008, 0, 0x05040002)});  // next blksize 0
  // Steps out of order.
  EXPECT_EQ(req({0xA3}), Frames{abort(0x1008, 0, 0x05040001)});
  EXPECT_EQ(req({0xA2, 1, 0x7F}), Frames{abort(0x1008, 0, 0x05040001)});
  EXPECT_EQ(req({0xA1}), Frames{abort(0x1008, 0, 0x05040001)});
  EXPECT_EQ(req({0xC1, 0, 0}), Frames{abort(0x1008, 0, 0x05040001)});
}

TEST_F(SdoBlockServer, UploadSwitchesToAPlainUploadAtOrBelowTheThreshold) {
  EXPECT_EQ(req({0xA4, 0x08, 0x10, 0x00, 0x7F, 14, 0, 0}), Frames{"<583> 41 08 10 00 0E 00 00 00"});
  EXPECT_EQ(req({0x60}), Frames{"<583> 00 6D 62 32 63 6F 20 49"});
  EXPECT_EQ(req({0x70}), Frames{"<583> 11 2F 4F 20 6E 6F 64 65"});
  EXPECT_EQ(req({0xA4, 0x08, 0x10, 0x00, 0x7F, 13, 0, 0}), Frames{"<583> C6 08 10 00 0E 00 00 00"});
  // A 2-byte value goes expedited.
  EXPECT_EQ(req({0xA4, 0x01, 0x21, 0x00, 0x7F, 4, 0, 0}), Frames{"<583> 4B 01 21 00 0A 00 00 00"});
}

TEST_F(SdoBlockServer, ASilentClientTimesOutAndADomainKeepsItsContent) {
  domain.content = pattern(100);
  const Bytes before = domain.content;
  EXPECT_EQ(req({0xC6, 0x50, 0x1F, 0x01, 70, 0, 0, 0}), Frames{"<583> A4 50 1F 01 7F 00 00 00"});
  const Bytes data = pattern(70, 9);
  for (uint8_t s = 1; s <= 5; ++s) seg(s, false, data, (s - 1u) * 7u);
  server.process(now + canopen::SdoServer::kDefaultTimeoutUs - 1, log.sink());
  EXPECT_EQ(log.take(), Frames{});
  server.process(now + canopen::SdoServer::kDefaultTimeoutUs, log.sink());
  EXPECT_EQ(log.take(), Frames{abort(0x1F50, 1, 0x05040000)});
  EXPECT_EQ(domain.content, before);
  EXPECT_EQ(domain.commits, 0);
  // A segmented download the client aborts: the old content stays too.
  EXPECT_EQ(req({0x21, 0x50, 0x1F, 0x01, 20, 0, 0, 0}), Frames{"<583> 60 50 1F 01 00 00 00 00"});
  EXPECT_EQ(req({0x00, 1, 2, 3, 4, 5, 6, 7}), Frames{"<583> 20 00 00 00 00 00 00 00"});
  EXPECT_EQ(req({0x80, 0x50, 0x1F, 0x01, 0, 0, 0, 8}), Frames{});
  EXPECT_FALSE(server.busy());
  EXPECT_EQ(domain.content, before);
  // And a complete one replaces it.
  EXPECT_EQ(req({0x21, 0x50, 0x1F, 0x01, 8, 0, 0, 0}), Frames{"<583> 60 50 1F 01 00 00 00 00"});
  EXPECT_EQ(req({0x00, 1, 2, 3, 4, 5, 6, 7}), Frames{"<583> 20 00 00 00 00 00 00 00"});
  EXPECT_EQ(req({0x1D, 8, 0, 0, 0, 0, 0, 0}), Frames{"<583> 30 00 00 00 00 00 00 00"});
  EXPECT_EQ(domain.content, (Bytes{1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST_F(SdoBlockServer, SegmentsRefusedByAFullTransmitQueueGoOutLater) {
  domain.content = pattern(30);
  req({0xA4, 0x50, 0x1F, 0x01, 0x7F, 0, 0, 0});
  log.refuse = true;
  req({0xA3});
  EXPECT_TRUE(log.frames.empty());
  NextDeadline d(now + 5);
  server.next_deadline(d);
  uint32_t at = 0;
  ASSERT_TRUE(d.result(&at));
  EXPECT_EQ(at, now + 5);  // due at once
  log.refuse = false;
  server.process(now + 5, log.sink());
  const Frames out = log.take();
  ASSERT_EQ(out.size(), 5u);  // 30 bytes: 4 full segments and one of 2
  EXPECT_EQ(out[4].substr(0, 8), "<583> 85");
}

TEST_F(SdoBlockServer, BlockTransferIsOffUnlessTurnedOn) {
  canopen::SdoServer plain{};  // as in every Node, and on the AVR
  plain.init(&io.od(), 3);
  plain.on_frame(frame({0xA4, 0x08, 0x10, 0x00, 0x7F}), now, log.sink());
  plain.on_frame(frame({0xC6, 0x00, 0x20, 0x00, 4}), now, log.sink());
  EXPECT_EQ(log.take(), (Frames{abort(0x1008, 0, 0x05040001), abort(0x2000, 0, 0x05040001)}));
  plain.set_block_transfer(true);
  plain.on_frame(frame({0xA4, 0x08, 0x10, 0x00, 0x7F}), now, log.sink());
  EXPECT_EQ(log.take(), Frames{"<583> C6 08 10 00 0E 00 00 00"});
}

TEST_F(SdoBlockServer, TheNodeServesItsDomainThroughTheHook) {
  io.node().sdo_server().set_domain(&table);
  domain.content = {0xDE, 0xAD};
  node_log.take();
  io.receive(F(0x603, {0x40, 0x50, 0x1F, 0x01, 0, 0, 0, 0}), 10);
  EXPECT_EQ(node_log.take(), Frames{"<583> 4B 50 1F 01 DE AD 00 00"});
  // Other objects still come from the OD.
  io.receive(F(0x603, {0x40, 0x01, 0x21, 0x00, 0, 0, 0, 0}), 20);
  EXPECT_EQ(node_log.take(), Frames{"<583> 4B 01 21 00 0A 00 00 00"});
  // Block transfer once the application turns it on.
  io.receive(F(0x603, {0xA4, 0x50, 0x1F, 0x01, 0x7F, 0, 0, 0}), 30);
  EXPECT_EQ(node_log.take(), Frames{abort(0x1F50, 1, 0x05040001)});
  io.node().sdo_server().set_block_transfer(true);
  io.receive(F(0x603, {0xA4, 0x50, 0x1F, 0x01, 0x7F, 0, 0, 0}), 40);
  EXPECT_EQ(node_log.take(), Frames{"<583> C6 50 1F 01 02 00 00 00"});
}

}  // namespace
}  // namespace test
}  // namespace mb2co
