// SdoClient against servers scripted byte by byte from CiA 301 §7.2.4.3:
// the exact frames the client sends, and what it does when a server breaks
// the protocol (wrong toggle, more or fewer bytes than announced, bad block
// size or sequence number, a wrong CRC, an unexpected command).
#include <gtest/gtest.h>

#include <algorithm>
#include <new>
#include <string>
#include <vector>

#include "canopen/od.h"
#include "canopen/sdo_client.h"
#include "frame_log.h"
#include "sdo_crc_reference.h"

namespace mb2co {
namespace test {
namespace {

using Frames = std::vector<std::string>;
using Bytes = std::vector<uint8_t>;
using canopen::SdoClient;

std::string hex_frame(uint16_t id, std::initializer_list<uint8_t> b) {
  CanFrame f = F(id, {0, 0, 0, 0, 0, 0, 0, 0});
  uint8_t i = 0;
  for (uint8_t x : b) f.data[i++] = x;
  return to_string(f);
}

class SdoClientScript : public ::testing::Test {
 protected:
  void SetUp() override { client.init(9); }

  /// A server frame on 589h (8 bytes, zeros after `b`); the client's answers.
  Frames srv(std::initializer_list<uint8_t> b) {
    CanFrame f = F(0x589, {0, 0, 0, 0, 0, 0, 0, 0});
    uint8_t i = 0;
    for (uint8_t x : b) f.data[i++] = x;
    client.on_frame(f, now, log.sink());
    return log.take();
  }
  /// A server frame: `cmd`, then 7 bytes of `data` from `offset`.
  Frames srv_data(uint8_t cmd, const Bytes& data, size_t offset) {
    CanFrame f = F(0x589, {cmd, 0, 0, 0, 0, 0, 0, 0});
    for (size_t i = 0; i < 7 && offset + i < data.size(); ++i) f.data[1 + i] = data[offset + i];
    client.on_frame(f, now, log.sink());
    return log.take();
  }
  static std::string req(std::initializer_list<uint8_t> b) { return hex_frame(0x609, b); }
  /// 7 data bytes from `offset` after command `cmd`, as the client sends them.
  static std::string req_data(uint8_t cmd, const Bytes& data, size_t offset) {
    CanFrame f = F(0x609, {cmd, 0, 0, 0, 0, 0, 0, 0});
    for (size_t i = 0; i < 7 && offset + i < data.size(); ++i) f.data[1 + i] = data[offset + i];
    return to_string(f);
  }
  static std::string abort(uint16_t index, uint8_t sub, uint32_t code) {
    return req({0x80, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), sub,
                static_cast<uint8_t>(code), static_cast<uint8_t>(code >> 8), static_cast<uint8_t>(code >> 16),
                static_cast<uint8_t>(code >> 24)});
  }
  void expect_failed(uint32_t code, bool by_server) {
    EXPECT_EQ(client.status(), SdoClient::kFailed);
    EXPECT_EQ(client.result(), code);
    EXPECT_EQ(client.aborted_by_server(), by_server);
    EXPECT_FALSE(client.busy());
  }

  FrameLog log;
  SdoClient client{};
  uint32_t now = 0;
  uint8_t buf[64] = {};
};

TEST_F(SdoClientScript, ExpeditedFrames) {
  const uint8_t v[2] = {0x2A, 0x00};
  ASSERT_TRUE(client.start_download(0x2101, 0, canopen::kSdoAuto, v, 2, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0x2B, 0x01, 0x21, 0x00, 0x2A, 0x00})});
  EXPECT_EQ(srv({0x60, 0x01, 0x21, 0x00}), Frames{});
  EXPECT_EQ(client.status(), SdoClient::kDone);
  // Upload answered without size indication (42h): four bytes.
  ASSERT_TRUE(client.start_upload(0x1000, 0, canopen::kSdoAuto, buf, 8, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0x40, 0x00, 0x10, 0x00})});
  EXPECT_EQ(srv({0x42, 0x00, 0x10, 0x00, 0x91, 0x01, 0x03, 0x00}), Frames{});
  EXPECT_EQ(client.status(), SdoClient::kDone);
  EXPECT_EQ(client.transferred(), 4u);
  EXPECT_EQ(canopen::le32(buf), 0x00030191u);
}

TEST_F(SdoClientScript, SegmentedDownloadFramesAndAWrongToggle) {
  const Bytes data = {'0', '1', '2', '3', '4', '5', '6', '7', '8', '9'};
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoAuto, data.data(), 10, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0x21, 0x00, 0x20, 0x00, 10, 0, 0, 0})});
  EXPECT_EQ(srv({0x60, 0x00, 0x20, 0x00}), Frames{req_data(0x00, data, 0)});
  // Toggle 1, n = 4 unused, c = 1: 10h | 08h | 01h.
  EXPECT_EQ(srv({0x20}), Frames{req_data(0x19, data, 7)});
  EXPECT_EQ(srv({0x30}), Frames{});
  EXPECT_EQ(client.status(), SdoClient::kDone);

  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoAuto, data.data(), 10, now, log.sink()));
  log.take();
  srv({0x60, 0x00, 0x20, 0x00});
  EXPECT_EQ(srv({0x20, 0, 0, 0, 0, 0, 0, 0}), Frames{req_data(0x19, data, 7)});
  EXPECT_EQ(srv({0x20}), Frames{abort(0x2000, 0, 0x05030000)});  // toggle 0 again
  expect_failed(0x05030000, false);
}

TEST_F(SdoClientScript, SegmentedUploadWithAWrongToggle) {
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoAuto, buf, 64, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0x40, 0x00, 0x20, 0x00})});
  EXPECT_EQ(srv({0x41, 0x00, 0x20, 0x00, 20, 0, 0, 0}), Frames{req({0x60})});
  EXPECT_EQ(srv({0x10, 'a', 'b', 'c', 'd', 'e', 'f', 'g'}), Frames{abort(0x2000, 0, 0x05030000)});
  expect_failed(0x05030000, false);
}

TEST_F(SdoClientScript, SegmentedUploadLongerOrShorterThanAnnounced) {
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoAuto, buf, 64, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0x41, 0x00, 0x20, 0x00, 10, 0, 0, 0}), Frames{req({0x60})});
  EXPECT_EQ(srv({0x00, 1, 2, 3, 4, 5, 6, 7}), Frames{req({0x70})});
  EXPECT_EQ(srv({0x11, 1, 2, 3, 4, 5, 6, 7}), Frames{abort(0x2000, 0, 0x06070012)});  // 14 > 10
  expect_failed(0x06070012, false);

  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoAuto, buf, 64, now, log.sink()));
  log.take();
  srv({0x41, 0x00, 0x20, 0x00, 10, 0, 0, 0});
  srv({0x00, 1, 2, 3, 4, 5, 6, 7});
  EXPECT_EQ(srv({0x1D, 8}), Frames{abort(0x2000, 0, 0x06070013)});  // 8 < 10, last
  expect_failed(0x06070013, false);
}

TEST_F(SdoClientScript, BlockDownloadFramesWithAResendFromTheAckseq) {
  Bytes data(20);
  for (uint8_t i = 0; i < 20; ++i) data[i] = static_cast<uint8_t>(0x41 + i);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 20, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0xC6, 0x00, 0x20, 0x00, 20, 0, 0, 0})});
  // The server takes 3 segments per sub-block and checks CRCs.
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 3}),
            (Frames{req_data(0x01, data, 0), req_data(0x02, data, 7), req_data(0x83, data, 14)}));
  EXPECT_EQ(client.transferred(), 0u);
  // Only segment 1 arrived; next sub-blocks of 3: the rest again from seqno 1.
  EXPECT_EQ(srv({0xA2, 1, 3}), (Frames{req_data(0x01, data, 7), req_data(0x82, data, 14)}));
  EXPECT_EQ(client.transferred(), 7u);
  const uint16_t crc = crc_ref(data);
  // n = 1 unused byte in the last segment: C1h | 1 << 2.
  EXPECT_EQ(srv({0xA2, 2, 3}),
            Frames{req({0xC5, static_cast<uint8_t>(crc), static_cast<uint8_t>(crc >> 8)})});
  EXPECT_EQ(client.transferred(), 20u);
  EXPECT_TRUE(client.busy());
  EXPECT_EQ(srv({0xA1}), Frames{});
  EXPECT_EQ(client.status(), SdoClient::kDone);
  EXPECT_TRUE(client.crc_used());
}

TEST_F(SdoClientScript, BlockDownloadWithoutServerCrcSendsNone) {
  const Bytes data = {1, 2, 3};
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 3, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xA0, 0x00, 0x20, 0x00, 127}), Frames{req({0x81, 1, 2, 3})});  // sc = 0
  EXPECT_EQ(srv({0xA2, 1, 127}), Frames{req({0xC1 | (4 << 2), 0, 0})});
  EXPECT_FALSE(client.crc_used());
}

TEST_F(SdoClientScript, BlockDownloadChecksBlockSizeAndSequenceNumber) {
  const Bytes data(30, 7);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 30, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 0}), Frames{abort(0x2000, 0, 0x05040002)});
  expect_failed(0x05040002, false);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 30, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 2}).size(), 2u);
  EXPECT_EQ(srv({0xA2, 3, 2}), Frames{abort(0x2000, 0, 0x05040003)});  // 3 of 2 sent
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 30, now, log.sink()));
  log.take();
  srv({0xA4, 0x00, 0x20, 0x00, 2});
  EXPECT_EQ(srv({0xA2, 2, 128}), Frames{abort(0x2000, 0, 0x05040002)});
}

TEST_F(SdoClientScript, BlockUploadFramesWithALostSegment) {
  Bytes data(15);
  for (uint8_t i = 0; i < 15; ++i) data[i] = static_cast<uint8_t>(100 + i);
  client.set_block_size(3);
  ASSERT_TRUE(client.start_upload(0x1008, 0, canopen::kSdoBlock, buf, 64, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{req({0xA4, 0x08, 0x10, 0x00, 3, 0})});
  EXPECT_EQ(srv({0xC6, 0x08, 0x10, 0x00, 15, 0, 0, 0}), Frames{req({0xA3})});
  EXPECT_EQ(srv_data(0x01, data, 0), Frames{});
  // Segment 2 is lost; 3 (the last, 1 byte) comes: ackseq 1, blksize 3.
  EXPECT_EQ(srv_data(0x83, data, 14), Frames{req({0xA2, 1, 3})});
  EXPECT_EQ(srv_data(0x01, data, 7), Frames{});
  EXPECT_EQ(srv_data(0x82, data, 14), Frames{req({0xA2, 2, 3})});
  const uint16_t crc = crc_ref(data);
  // n = 6: C1h | 6 << 2.
  EXPECT_EQ(srv({0xD9, static_cast<uint8_t>(crc), static_cast<uint8_t>(crc >> 8)}), Frames{req({0xA1})});
  EXPECT_EQ(client.status(), SdoClient::kDone);
  EXPECT_EQ(client.transferred(), 15u);
  EXPECT_EQ(Bytes(buf, buf + 15), data);
  EXPECT_EQ(buf[15], 0);  // nothing written past the data (the padding of the last segment)
}

TEST(SdoClientPst, ADefaultInitialisedClientOffersNoProtocolSwitch) {
  // mb2co-master holds its clients default-initialised (SdoNetwork's
  // Node nodes_[128]), not zeroed: pst (byte 5 of the block upload
  // initiate) must still be 0 unless set_switch_threshold() said otherwise
  // (CiA 301: pst 0, no change of protocol). npm's canopen server reads
  // bytes 4..7 as one 32-bit blksize, so a stray pst broke the transfer.
  alignas(SdoClient) unsigned char storage[sizeof(SdoClient)];
  std::fill(storage, storage + sizeof storage, 0xFF);  // what a used stack may hold
  SdoClient* c = new (storage) SdoClient;              // default-initialised, as in SdoNetwork
  FrameLog log;
  uint8_t buf[8] = {};
  c->init(9);
  ASSERT_TRUE(c->start_upload(0x1018, 1, canopen::kSdoBlock, buf, sizeof buf, 0, log.sink()));
  EXPECT_EQ(log.take(), Frames{hex_frame(0x609, {0xA4, 0x18, 0x10, 0x01, 127, 0})});
  c->~SdoClient();
}

TEST_F(SdoClientScript, BlockUploadWithAWrongCrcOrMoreThanAnnounced) {
  const Bytes data(14, 0x55);
  ASSERT_TRUE(client.start_upload(0x1008, 0, canopen::kSdoBlock, buf, 64, now, log.sink()));
  log.take();
  srv({0xC6, 0x08, 0x10, 0x00, 14, 0, 0, 0});
  srv_data(0x01, data, 0);
  EXPECT_EQ(srv_data(0x82, data, 7), Frames{req({0xA2, 2, 127})});
  const uint16_t bad = static_cast<uint16_t>(crc_ref(data) ^ 1);
  EXPECT_EQ(srv({0xC1, static_cast<uint8_t>(bad), static_cast<uint8_t>(bad >> 8)}),
            Frames{abort(0x1008, 0, 0x05040004)});
  expect_failed(0x05040004, false);

  // Announced 10, the segments carry 14.
  ASSERT_TRUE(client.start_upload(0x1008, 0, canopen::kSdoBlock, buf, 64, now, log.sink()));
  log.take();
  srv({0xC6, 0x08, 0x10, 0x00, 10, 0, 0, 0});
  srv_data(0x01, data, 0);
  srv_data(0x82, data, 7);
  const uint16_t crc = crc_ref(data);
  EXPECT_EQ(srv({0xC1, static_cast<uint8_t>(crc), static_cast<uint8_t>(crc >> 8)}),
            Frames{abort(0x1008, 0, 0x06070012)});
}

TEST_F(SdoClientScript, UnexpectedAnswersAreAborted) {
  const uint8_t v[1] = {1};
  ASSERT_TRUE(client.start_download(0x2101, 0, canopen::kSdoAuto, v, 1, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0x41, 0x01, 0x21, 0x00}), Frames{abort(0x2101, 0, 0x05040001)});  // an upload answer
  ASSERT_TRUE(client.start_download(0x2101, 0, canopen::kSdoAuto, v, 1, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0x60, 0x02, 0x21, 0x00}), Frames{abort(0x2101, 0, 0x06040043)});  // another object
}

TEST_F(SdoClientScript, AServerAbortEndsABlockTransferWithItsCode) {
  const Bytes data(100, 1);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 100, now, log.sink()));
  log.take();
  srv({0xA4, 0x00, 0x20, 0x00, 127});
  EXPECT_EQ(srv({0x80, 0x00, 0x20, 0x00, 0x22, 0x00, 0x00, 0x08}), Frames{});
  expect_failed(0x08000022, true);
}

TEST_F(SdoClientScript, OtherCobIdsAndMalformedFrames) {
  client.set_cob_ids(0x640, 0x5C0);
  ASSERT_TRUE(client.start_upload(0x1000, 0, canopen::kSdoAuto, buf, 8, now, log.sink()));
  EXPECT_EQ(log.take(), Frames{hex_frame(0x640, {0x40, 0x00, 0x10, 0x00})});
  EXPECT_EQ(srv({0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}), Frames{});  // on 589h: not ours
  CanFrame shortf = F(0x5C0, {0x43, 0x00, 0x10, 0x00, 1, 2, 3});
  client.on_frame(shortf, now, log.sink());
  CanFrame rtr = Rtr(0x5C0, 8);
  client.on_frame(rtr, now, log.sink());
  EXPECT_TRUE(client.busy());
  client.on_frame(F(0x5C0, {0x43, 0x00, 0x10, 0x00, 1, 2, 3, 4}), now, log.sink());
  EXPECT_EQ(client.status(), SdoClient::kDone);
  EXPECT_EQ(canopen::le32(buf), 0x04030201u);
}

TEST_F(SdoClientScript, SegmentsRefusedByAFullTransmitQueueGoOutFromProcess) {
  const Bytes data(21, 3);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 21, now, log.sink()));
  log.take();
  log.refuse = true;
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 127}), Frames{});
  NextDeadline d(now + 3);
  client.next_deadline(d);
  uint32_t at = 0;
  ASSERT_TRUE(d.result(&at));
  EXPECT_EQ(at, now + 3);
  log.refuse = false;
  client.process(now + 3, log.sink());
  EXPECT_EQ(log.take(), (Frames{req_data(0x01, data, 0), req_data(0x02, data, 7), req_data(0x83, data, 14)}));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
