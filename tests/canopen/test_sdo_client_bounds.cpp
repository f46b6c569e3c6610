// SdoClient against servers that keep answering without end (issue 22 item
// 4): every transfer ends. The timeout runs from the last progress, not from
// the last frame; sub-blocks repeated in a row are bounded; bytes beyond the
// indicated size or the caller's capacity end the transfer at the frame that
// shows them. Servers scripted frame by frame, time given by hand.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopen/sdo_client.h"
#include "frame_log.h"

namespace mb2co {
namespace test {
namespace {

using Frames = std::vector<std::string>;
using Bytes = std::vector<uint8_t>;
using canopen::SdoClient;

const uint32_t kTimeoutUs = 300000;
/// SdoClient::kBlockRepeatsMax, as docs/mb2co-master.md gives it.
const int kRepeatsMax = 8;

class SdoClientBounds : public ::testing::Test {
 protected:
  void SetUp() override {
    client.init(9);
    client.set_timeout_us(kTimeoutUs);
  }

  /// A server frame on 589h at `now` (8 bytes, zeros after `b`); the client's answers.
  Frames srv(std::initializer_list<uint8_t> b) {
    CanFrame f = F(0x589, {0, 0, 0, 0, 0, 0, 0, 0});
    uint8_t i = 0;
    for (uint8_t x : b) f.data[i++] = x;
    client.on_frame(f, now, log.sink());
    return log.take();
  }
  /// A block segment: seqno | c, 7 bytes of 0x5A.
  Frames seg(uint8_t seqno, bool last = false) {
    return srv({static_cast<uint8_t>(seqno | (last ? 0x80 : 0)), 0x5A, 0x5A, 0x5A, 0x5A, 0x5A, 0x5A, 0x5A});
  }
  Frames process() {
    client.process(now, log.sink());
    return log.take();
  }
  static std::string req(std::initializer_list<uint8_t> b) {
    CanFrame f = F(0x609, {0, 0, 0, 0, 0, 0, 0, 0});
    uint8_t i = 0;
    for (uint8_t x : b) f.data[i++] = x;
    return to_string(f);
  }
  static std::string abort(uint32_t code) {
    return req({0x80, 0x00, 0x20, 0x00, static_cast<uint8_t>(code), static_cast<uint8_t>(code >> 8),
                static_cast<uint8_t>(code >> 16), static_cast<uint8_t>(code >> 24)});
  }
  void expect_sent(uint32_t code) {
    EXPECT_EQ(client.status(), SdoClient::kFailed);
    EXPECT_EQ(client.result(), code);
    EXPECT_FALSE(client.aborted_by_server());
  }

  FrameLog log;
  SdoClient client{};
  uint32_t now = 1000;
  uint8_t buf[64] = {};
};

TEST_F(SdoClientBounds, EmptySegmentsForeverAreNoProgressAndTimeOut) {
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoAuto, buf, 64, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0x40, 0x00, 0x20, 0x00}), Frames{req({0x60})});  // no size: the last progress
  const uint32_t progress_us = now;
  // Every 50 ms an empty segment with more to follow, the toggle right:
  // valid answers that move nothing.
  uint8_t toggle = 0;
  for (now = progress_us + 50000; now - progress_us < kTimeoutUs; now += 50000) {
    EXPECT_EQ(srv({static_cast<uint8_t>(toggle | 0x0E)}), Frames{req({static_cast<uint8_t>(0x70 ^ toggle)})});
    toggle ^= 0x10;
    EXPECT_EQ(process(), Frames{});
  }
  now = progress_us + kTimeoutUs;
  EXPECT_EQ(process(), Frames{abort(0x05040000)});
  expect_sent(0x05040000);
}

TEST_F(SdoClientBounds, BlockDownloadAckedWithNothingEndsAfterTheRepeatBound) {
  const Bytes data(100, 1);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 100, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 3}).size(), 3u);  // a sub-block of 3 segments
  // The server acks none of them, at once, again and again: each ack makes
  // us send the sub-block again, kBlockRepeatsMax times.
  for (int i = 0; i < kRepeatsMax; ++i) EXPECT_EQ(srv({0xA2, 0, 3}).size(), 3u) << i;
  EXPECT_EQ(srv({0xA2, 0, 3}), Frames{abort(0x05040003)});
  expect_sent(0x05040003);
}

TEST_F(SdoClientBounds, APartialAckCountsAsARepeatAndAWholeOneResetsTheCount) {
  const Bytes data(2000, 1);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 2000, now, log.sink()));
  log.take();
  srv({0xA4, 0x00, 0x20, 0x00, 2});
  for (int round = 0; round < 3; ++round) {
    // One of two segments taken, kBlockRepeatsMax times: progress, but
    // every sub-block must be repeated.
    for (int i = 0; i < kRepeatsMax; ++i) EXPECT_EQ(srv({0xA2, 1, 2}).size(), 2u) << i;
    EXPECT_EQ(srv({0xA2, 2, 2}).size(), 2u);  // a whole sub-block: the count starts again
  }
  for (int i = 0; i < kRepeatsMax; ++i) srv({0xA2, 1, 2});
  EXPECT_EQ(srv({0xA2, 1, 2}), Frames{abort(0x05040003)});
  expect_sent(0x05040003);
}

TEST_F(SdoClientBounds, BlockDownloadAckedWithNothingTimesOutFromTheLastProgress) {
  const Bytes data(100, 1);
  ASSERT_TRUE(client.start_download(0x2000, 0, canopen::kSdoBlock, data.data(), 100, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xA4, 0x00, 0x20, 0x00, 3}).size(), 3u);
  const uint32_t progress_us = now;
  // Slow acks of nothing, fewer than the repeat bound: each sub-block sent
  // again in full, yet the timeout keeps running from the initiate.
  for (now = progress_us + 100000; now - progress_us < kTimeoutUs; now += 100000) {
    EXPECT_EQ(srv({0xA2, 0, 3}).size(), 3u);
    EXPECT_EQ(process(), Frames{});
  }
  now = progress_us + kTimeoutUs;
  EXPECT_EQ(process(), Frames{abort(0x05040000)});
  expect_sent(0x05040000);
}

TEST_F(SdoClientBounds, BlockUploadOutOfSequenceForeverEndsAfterTheRepeatBound) {
  client.set_block_size(3);
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoBlock, buf, 64, now, log.sink()));
  log.take();
  EXPECT_EQ(srv({0xC6, 0x00, 0x20, 0x00, 60, 0, 0, 0}), Frames{req({0xA3})});
  // Segment 1 never comes: segments 2 and 3, then the ack of nothing.
  for (int i = 0; i < kRepeatsMax; ++i) {
    EXPECT_EQ(seg(2), Frames{});
    EXPECT_EQ(seg(3), Frames{req({0xA2, 0, 3})}) << i;
  }
  EXPECT_EQ(seg(2), Frames{});
  EXPECT_EQ(seg(3), Frames{abort(0x05040003)});
  expect_sent(0x05040003);
}

TEST_F(SdoClientBounds, BlockUploadBeyondTheIndicatedSizeEndsAtTheFullSegmentThatShowsIt) {
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoBlock, buf, 64, now, log.sink()));
  log.take();
  srv({0xC6, 0x00, 0x20, 0x00, 10, 0, 0, 0});
  EXPECT_EQ(seg(1), Frames{});
  // A second segment with c = 0 carries 7 more bytes: 14 > 10, now.
  EXPECT_EQ(seg(2), Frames{abort(0x06070012)});
  expect_sent(0x06070012);
}

TEST_F(SdoClientBounds, BlockUploadWithoutSizeStopsAtTheCapacity) {
  ASSERT_TRUE(client.start_upload(0x2000, 0, canopen::kSdoBlock, buf, 20, now, log.sink()));
  log.take();
  srv({0xC4, 0x00, 0x20, 0x00});  // no size indicated
  EXPECT_EQ(seg(1), Frames{});
  EXPECT_EQ(seg(2), Frames{});
  EXPECT_EQ(seg(3), Frames{abort(0x05040005)});  // 21 > 20, known before it is stored
  expect_sent(0x05040005);
  EXPECT_EQ(client.transferred(), 14u);  // stored: the first two segments, never the third
}

}  // namespace
}  // namespace test
}  // namespace mb2co
