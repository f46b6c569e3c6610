// SdoClient against our SdoServer in one process (frames through an SdoBus in
// virtual time): every transfer kind and size, block size negotiation, lost
// and corrupted frames, timeouts, aborts from both ends, the protocol switch,
// and several transfers at once. Scripted servers where the server must
// misbehave (test_sdo_client_script.cpp).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "canopen/sdo_client.h"
#include "canopen/sdo_server.h"
#include "ionode/io_node.h"
#include "test_sdo_client_link.h"

namespace mb2co {
namespace test {
namespace {

using canopen::SdoAbort;
using canopen::SdoClient;
using canopen::SdoMode;
using Bytes = std::vector<uint8_t>;

const uint16_t kDomainIndex = 0x1F50;
const uint8_t kDomainSub = 1;

bool is_abort(const CanFrame& f, uint32_t id, uint32_t code) {
  return f.id == id && f.dlc == 8 && f.data[0] == 0x80 && canopen::le32(&f.data[4]) == code;
}

class SdoClientTest : public ::testing::Test {
 protected:
  static const uint8_t kId = 5;

  void SetUp() override {
    io.start(kId, 0);
    server.init(&io.od(), kId);
    domain_table = domain.table();
    server.set_domain(&domain_table);
    server.set_block_transfer(true);
    client.init(kId);
    bus.servers.push_back({&server, kId});
    bus.clients.push_back(&client);
  }

  SdoAbort download(SdoMode mode, const Bytes& data, uint16_t index = kDomainIndex,
                    uint8_t sub = kDomainSub) {
    bus.log.clear();
    EXPECT_TRUE(client.start_download(index, sub, mode, data.data(), static_cast<uint32_t>(data.size()),
                                      bus.now, bus.sink()));
    bus.run();
    EXPECT_FALSE(client.busy());
    return client.result();
  }

  SdoAbort upload(SdoMode mode, Bytes* out, uint32_t capacity, uint16_t index = kDomainIndex,
                  uint8_t sub = kDomainSub) {
    bus.log.clear();
    out->assign(capacity, 0xEE);
    EXPECT_TRUE(client.start_upload(index, sub, mode, out->data(), capacity, bus.now, bus.sink()));
    bus.run();
    EXPECT_FALSE(client.busy());
    if (client.result() == canopen::kSdoOk) out->resize(client.transferred());
    return client.result();
  }

  /// Frames on `id` whose byte 0 satisfies `pred`.
  template <class Pred>
  size_t count(uint32_t id, Pred pred) const {
    size_t n = 0;
    for (const CanFrame& f : bus.log) {
      if (f.id == id && pred(f.data[0])) ++n;
    }
    return n;
  }

  FrameLog node_log;
  ionode::IoNode io{node_log.sink()};
  canopen::SdoServer server{};
  SdoClient client{};
  RamDomain domain{kDomainIndex, kDomainSub, 1u << 20};
  canopen::SdoDomain domain_table{};
  SdoBus bus;
};

// Sizes 0..889 in each mode, down and up again: expedited where it applies,
// segments with partial last segments, sub-blocks of 127 segments (889 = 127 * 7).
TEST_F(SdoClientTest, EveryModeMovesEverySizeUpTo889BytesBothWays) {
  const SdoMode modes[] = {canopen::kSdoAuto, canopen::kSdoSegmented, canopen::kSdoBlock};
  for (SdoMode mode : modes) {
    for (uint32_t n = 0; n <= 889; ++n) {
      SCOPED_TRACE("mode " + std::to_string(mode) + " size " + std::to_string(n));
      const Bytes data = pattern(n, n + mode);
      ASSERT_EQ(download(mode, data), canopen::kSdoOk);
      ASSERT_EQ(domain.content, data);
      ASSERT_EQ(client.transferred(), n);
      const bool expedited = mode == canopen::kSdoAuto && n >= 1 && n <= 4;
      if (expedited) {
        ASSERT_EQ(bus.log.size(), 2u);
      }
      if (mode == canopen::kSdoBlock) {
        ASSERT_EQ(bus.log.front().data[0], 0xC6);  // block initiate, CRC, size
      }
      if (mode == canopen::kSdoBlock) {
        ASSERT_TRUE(client.crc_used());
      }

      Bytes back;
      ASSERT_EQ(upload(mode, &back, n), canopen::kSdoOk);  // a buffer of exactly n bytes suffices
      ASSERT_EQ(back, data);
      ASSERT_TRUE(client.size_known());
      ASSERT_EQ(client.size(), n);
      // The server answers 1..4 bytes expedited to a plain upload request.
      if (mode != canopen::kSdoBlock && n >= 1 && n <= 4) {
        ASSERT_EQ(bus.log.size(), 2u);
      }
      if (mode == canopen::kSdoBlock) {
        ASSERT_EQ(bus.log.front().data[0], 0xA4);  // block upload initiate
      }
      ASSERT_FALSE(server.busy());
    }
  }
}

TEST_F(SdoClientTest, OdValuesExpeditedAndSegmented) {
  ASSERT_EQ(download(canopen::kSdoAuto, {42, 0}, 0x2101, 0), canopen::kSdoOk);
  EXPECT_EQ(io.od().get(io.od().find(0x2101, 0)), 42u);
  Bytes name;
  ASSERT_EQ(upload(canopen::kSdoAuto, &name, 64, 0x1008, 0), canopen::kSdoOk);
  EXPECT_EQ(std::string(name.begin(), name.end()), "mb2co I/O node");
  // The OD's own block path (buffered, not a domain): a string down and up.
  const std::string label = "hall 3, line 2, station";
  ASSERT_EQ(download(canopen::kSdoBlock, Bytes(label.begin(), label.end()), 0x2000, 0), canopen::kSdoOk);
  Bytes back;
  ASSERT_EQ(upload(canopen::kSdoBlock, &back, 64, 0x2000, 0), canopen::kSdoOk);
  EXPECT_EQ(std::string(back.begin(), back.end()), label);
}

// >= 64 KiB through SdoData streams (no buffer of the whole object on the
// client side), block and segmented, with the progress counter rising.
TEST_F(SdoClientTest, LargeObjectsBlockAndSegmentedThroughStreams) {
  const uint32_t n = 70001;  // 10000 segments and 1 byte: a partial last segment
  const SdoMode modes[] = {canopen::kSdoBlock, canopen::kSdoSegmented};
  for (SdoMode mode : modes) {
    SCOPED_TRACE(mode);
    VectorData src;
    src.bytes = pattern(n, 7 + mode);
    std::vector<uint32_t> progress;
    bus.tamper = [&](CanFrame&) {
      progress.push_back(client.transferred());
      return true;
    };
    ASSERT_TRUE(client.start_download(kDomainIndex, kDomainSub, mode, src.data(), n, bus.now, bus.sink()));
    bus.run();
    ASSERT_EQ(client.result(), canopen::kSdoOk);
    EXPECT_EQ(domain.content, src.bytes);
    EXPECT_EQ(client.transferred(), n);
    for (size_t i = 1; i < progress.size(); ++i) ASSERT_LE(progress[i - 1], progress[i]);
    EXPECT_GT(progress.size(), 10000u);
    EXPECT_GT(progress[progress.size() / 2], n / 4);  // it rises along the way, not at the end only

    VectorData dst;
    ASSERT_TRUE(
        client.start_upload(kDomainIndex, kDomainSub, mode, dst.data(), 0xFFFFFFFFu, bus.now, bus.sink()));
    bus.run();
    ASSERT_EQ(client.result(), canopen::kSdoOk);
    EXPECT_EQ(dst.bytes, src.bytes);
    bus.tamper = nullptr;
  }
}

TEST_F(SdoClientTest, BlockSizeIsNegotiatedByTheReceiver) {
  // Download: the server asks for 5 segments per sub-block.
  server.set_block_size(5);
  const Bytes data = pattern(100);  // 15 segments: 5 + 5 + 5
  ASSERT_EQ(download(canopen::kSdoBlock, data), canopen::kSdoOk);
  EXPECT_EQ(domain.content, data);
  EXPECT_EQ(bus.log[1].data[4], 5);  // initiate response: blksize 5
  EXPECT_EQ(count(0x585, [](uint8_t b) { return b == 0xA2; }), 3u);
  // Between the initiate (first) and the end request (last), every frame of
  // the client is a segment: runs of seqno 1..5, each closed by an ack.
  size_t run = 0;
  size_t last = 0;
  for (size_t i = 0; i < bus.log.size(); ++i) {
    if (bus.log[i].id == 0x605) last = i;
  }
  for (size_t i = 1; i < last; ++i) {  // bus.log[0]: the initiate
    const CanFrame& f = bus.log[i];
    if (f.id == 0x605) {
      ++run;
      EXPECT_EQ(f.data[0] & 0x7F, run);
    } else if (f.data[0] == 0xA2) {
      EXPECT_EQ(f.data[1], 5);  // all 5 arrived
      EXPECT_EQ(f.data[2], 5);
      EXPECT_EQ(run, 5u);
      run = 0;
    }
  }
  // Upload: we ask for 9; 15 segments come as 9 + 6.
  client.set_block_size(9);
  Bytes back;
  ASSERT_EQ(upload(canopen::kSdoBlock, &back, 200), canopen::kSdoOk);
  EXPECT_EQ(back, data);
  EXPECT_EQ(bus.log[0].data[4], 9);
  const size_t segments = count(0x585, [](uint8_t b) { return (b & 0x7F) >= 1 && (b & 0x7F) <= 9; });
  EXPECT_EQ(segments, 15u);
  EXPECT_EQ(count(0x605, [](uint8_t b) { return b == 0xA2; }), 2u);
}

TEST_F(SdoClientTest, BlockDownloadResendsFromTheServersAckseqAfterALostSegment) {
  const Bytes data = pattern(2000, 3);  // 286 segments: sub-blocks of 127
  bool dropped = false;
  bus.tamper = [&](CanFrame& f) {
    if (!dropped && f.id == 0x605 && f.data[0] == 40) {  // seqno 40 of the first sub-block
      dropped = true;
      return false;
    }
    return true;
  };
  ASSERT_EQ(download(canopen::kSdoBlock, data), canopen::kSdoOk);
  EXPECT_TRUE(dropped);
  EXPECT_EQ(domain.content, data);
  EXPECT_TRUE(client.crc_used());
  // The first ack names the 39 segments that arrived in sequence; the next
  // sub-block starts with byte 39 * 7 at seqno 1.
  size_t i = 0;
  while (!(bus.log[i].id == 0x585 && bus.log[i].data[0] == 0xA2)) ++i;
  EXPECT_EQ(bus.log[i].data[1], 39);
  EXPECT_EQ(bus.log[i + 1].data[0], 1);
  EXPECT_EQ(Bytes(&bus.log[i + 1].data[1], &bus.log[i + 1].data[8]), Bytes(&data[273], &data[280]));
  EXPECT_EQ(domain.commits, 1);
}

TEST_F(SdoClientTest, BlockUploadAcksTheLastSegmentInSequenceAndGetsTheRestAgain) {
  domain.content = pattern(1500, 9);
  int dropped = 0;
  bus.tamper = [&](CanFrame& f) {
    if (dropped == 0 && f.id == 0x585 && f.data[0] == 4) {  // seqno 4 of the first sub-block
      ++dropped;
      return false;
    }
    return true;
  };
  Bytes back;
  client.set_block_size(20);
  ASSERT_EQ(upload(canopen::kSdoBlock, &back, 1500), canopen::kSdoOk);
  EXPECT_EQ(back, domain.content);
  EXPECT_EQ(dropped, 1);
  size_t i = 0;
  while (!(bus.log[i].id == 0x605 && bus.log[i].data[0] == 0xA2)) ++i;
  EXPECT_EQ(bus.log[i].data[1], 3);  // ackseq: 1..3 arrived in sequence
  EXPECT_EQ(bus.log[i + 1].data[0], 1);
  EXPECT_EQ(Bytes(&bus.log[i + 1].data[1], &bus.log[i + 1].data[8]), Bytes(&back[21], &back[28]));
}

TEST_F(SdoClientTest, ACorruptedDataByteInABlockDownloadFailsTheCrcAtTheServer) {
  domain.content = pattern(10, 1);
  const Bytes before = domain.content;
  bus.tamper = [&](CanFrame& f) {
    if (f.id == 0x605 && f.data[0] == 17) f.data[3] ^= 0x01;  // a bit flipped on the way
    return true;
  };
  EXPECT_EQ(download(canopen::kSdoBlock, pattern(1000, 2)), canopen::kAbortCrc);
  EXPECT_TRUE(client.aborted_by_server());
  EXPECT_EQ(domain.content, before);  // nothing committed
  EXPECT_FALSE(server.busy());
}

TEST_F(SdoClientTest, ACorruptedCrcInTheBlockUploadEndIsAbortedByTheClient) {
  domain.content = pattern(300, 4);
  bus.tamper = [&](CanFrame& f) {
    if (f.id == 0x585 && (f.data[0] & 0xE3) == 0xC1) f.data[2] ^= 0x40;
    return true;
  };
  Bytes back;
  EXPECT_EQ(upload(canopen::kSdoBlock, &back, 300), canopen::kAbortCrc);
  EXPECT_FALSE(client.aborted_by_server());
  EXPECT_TRUE(is_abort(bus.log.back(), 0x605, canopen::kAbortCrc));
  EXPECT_FALSE(server.busy());  // the server got the abort and let go
}

TEST_F(SdoClientTest, ASilentServerIsAbortedAtTheTimeout) {
  client.set_timeout_us(200000);
  bus.servers.clear();  // nobody answers
  bus.now = 1000;
  ASSERT_TRUE(client.start_upload(0x1008, 0, canopen::kSdoAuto, nullptr, 0, bus.now, bus.sink()));
  ASSERT_TRUE(bus.step());
  NextDeadline d(bus.now);
  client.next_deadline(d);
  uint32_t at = 0;
  ASSERT_TRUE(d.result(&at));
  EXPECT_EQ(at, 201000u);
  client.process(200999, bus.sink());
  EXPECT_TRUE(client.busy());
  EXPECT_EQ(bus.queued(), 0u);
  client.process(201000, bus.sink());
  EXPECT_EQ(client.status(), SdoClient::kFailed);
  EXPECT_EQ(client.result(), canopen::kAbortTimeout);
  EXPECT_FALSE(client.aborted_by_server());
  ASSERT_TRUE(bus.step());
  EXPECT_EQ(to_string(bus.log.back()), "<605> 80 08 10 00 00 00 04 05");
}

TEST_F(SdoClientTest, ALostBlockAckTimesOutAndTheAbortFreesTheServer) {
  client.set_timeout_us(200000);  // shorter than the server's 1 s
  domain.content = pattern(5, 5);
  const Bytes before = domain.content;
  bus.tamper = [](CanFrame& f) { return !(f.id == 0x585 && f.data[0] == 0xA2); };
  EXPECT_EQ(download(canopen::kSdoBlock, pattern(100)), canopen::kAbortTimeout);
  EXPECT_FALSE(client.aborted_by_server());
  EXPECT_TRUE(is_abort(bus.log.back(), 0x605, canopen::kAbortTimeout));
  EXPECT_FALSE(server.busy());
  EXPECT_EQ(domain.content, before);
}

TEST_F(SdoClientTest, TheServersAbortCodeIsPassedUpUnchanged) {
  Bytes out;
  EXPECT_EQ(upload(canopen::kSdoAuto, &out, 8, 0x5555, 0), canopen::kAbortNoObject);
  EXPECT_TRUE(client.aborted_by_server());
  EXPECT_EQ(download(canopen::kSdoAuto, {1, 2}, 0x1008, 0), canopen::kAbortReadOnly);
  EXPECT_TRUE(client.aborted_by_server());
  EXPECT_EQ(download(canopen::kSdoAuto, {0, 1}, 0x2101, 0), canopen::kAbortValueTooHigh);  // 256 > 250
  EXPECT_EQ(download(canopen::kSdoBlock, pattern(30), 0x1008, 0), canopen::kAbortReadOnly);
  EXPECT_EQ(upload(canopen::kSdoBlock, &out, 8, 0x1008, 7), canopen::kAbortNoSubindex);
  // A block download longer than the object: refused at the initiate.
  EXPECT_EQ(download(canopen::kSdoBlock, pattern(25), 0x2000, 0), canopen::kAbortTooLong);
  for (const CanFrame& f : bus.log)
    EXPECT_FALSE(f.id == 0x605 && f.data[0] == 0x80) << "the client sent an abort";
}

TEST_F(SdoClientTest, ABufferTooSmallEndsWithOutOfMemorySentToTheServer) {
  domain.content = pattern(100);
  const SdoMode modes[] = {canopen::kSdoAuto, canopen::kSdoBlock};
  for (SdoMode mode : modes) {
    Bytes out;
    EXPECT_EQ(upload(mode, &out, 99), canopen::kAbortOutOfMemory);
    EXPECT_FALSE(client.aborted_by_server());
    EXPECT_TRUE(is_abort(bus.log.back(), 0x605, canopen::kAbortOutOfMemory));
    EXPECT_EQ(bus.log.size(), 3u);  // request, answer with the size, abort: no data moved
    EXPECT_FALSE(server.busy());
  }
  // Expedited answers too: 3 bytes into 2.
  domain.content = pattern(3);
  Bytes out;
  EXPECT_EQ(upload(canopen::kSdoAuto, &out, 2), canopen::kAbortOutOfMemory);
}

TEST_F(SdoClientTest, BlockUploadSwitchesToAPlainUploadBelowTheThreshold) {
  client.set_switch_threshold(16);
  Bytes name;
  ASSERT_EQ(upload(canopen::kSdoBlock, &name, 64, 0x1008, 0), canopen::kSdoOk);  // 14 bytes <= 16
  EXPECT_EQ(std::string(name.begin(), name.end()), "mb2co I/O node");
  EXPECT_EQ(bus.log[0].data[5], 16);    // pst in the request
  EXPECT_EQ(bus.log[1].data[0], 0x41);  // a segmented upload answer
  EXPECT_EQ(bus.log[2].data[0], 0x60);  // and segment requests follow
  domain.content = pattern(3);
  Bytes small;
  ASSERT_EQ(upload(canopen::kSdoBlock, &small, 8), canopen::kSdoOk);
  EXPECT_EQ(small, domain.content);
  EXPECT_EQ(bus.log.size(), 2u);  // expedited
  domain.content = pattern(17);   // above the threshold: a block transfer
  ASSERT_EQ(upload(canopen::kSdoBlock, &small, 32), canopen::kSdoOk);
  EXPECT_EQ(small, domain.content);
  EXPECT_EQ(bus.log[1].data[0], 0xC6);
}

TEST_F(SdoClientTest, TheWatchdogsAbortEndsATransferOnBothEnds) {
  domain.content = pattern(8);
  const Bytes before = domain.content;
  const Bytes data = pattern(5000);
  ASSERT_TRUE(client.start_download(kDomainIndex, kDomainSub, canopen::kSdoBlock, data.data(), 5000, bus.now,
                                    bus.sink()));
  for (int i = 0; i < 50; ++i) bus.step();
  ASSERT_TRUE(client.busy());
  ASSERT_TRUE(server.busy());
  client.abort(canopen::kAbortGeneral, bus.sink());
  EXPECT_EQ(client.status(), SdoClient::kFailed);
  EXPECT_EQ(client.result(), canopen::kAbortGeneral);
  bus.run();  // the segments already queued, then the abort
  size_t aborts = 0;
  for (const CanFrame& f : bus.log) aborts += is_abort(f, 0x605, canopen::kAbortGeneral) ? 1u : 0u;
  EXPECT_EQ(aborts, 1u);
  EXPECT_FALSE(server.busy());
  EXPECT_EQ(domain.content, before);
  EXPECT_EQ(domain.commits, 0);
  // The channel is free again.
  EXPECT_EQ(download(canopen::kSdoBlock, data), canopen::kSdoOk);
  EXPECT_EQ(domain.content, data);
}

TEST_F(SdoClientTest, ABusyClientRefusesASecondTransfer) {
  Bytes out(8);
  ASSERT_TRUE(client.start_upload(0x1008, 0, canopen::kSdoAuto, out.data(), 8, bus.now, bus.sink()));
  EXPECT_FALSE(client.start_upload(0x1000, 0, canopen::kSdoAuto, out.data(), 8, bus.now, bus.sink()));
  EXPECT_FALSE(client.start_download(0x2101, 0, canopen::kSdoAuto, out.data(), 2, bus.now, bus.sink()));
  EXPECT_EQ(bus.queued(), 1u);
}

// Three masters' channels at once on one bus, frames interleaved: each
// client talks to its own server only (COB-IDs), each gets its own data.
TEST(SdoClientConcurrency, ThreeClientsToThreeServersInterleaved) {
  FrameLog node_log;
  ionode::IoNode io{node_log.sink()};
  io.start(1, 0);
  SdoBus bus;
  canopen::SdoServer servers[3] = {};
  SdoClient clients[3] = {};
  RamDomain domains[3] = {{kDomainIndex, kDomainSub, 1u << 20},
                          {kDomainIndex, kDomainSub, 1u << 20},
                          {kDomainIndex, kDomainSub, 1u << 20}};
  canopen::SdoDomain tables[3];
  const uint8_t ids[3] = {10, 11, 127};
  for (int k = 0; k < 3; ++k) {
    servers[k].init(&io.od(), ids[k]);
    tables[k] = domains[k].table();
    servers[k].set_domain(&tables[k]);
    servers[k].set_block_transfer(true);
    domains[k].content = pattern(3000 + 100 * static_cast<uint32_t>(k), static_cast<uint32_t>(k) * 50);
    clients[k].init(ids[k]);
    bus.servers.push_back({&servers[k], ids[k]});
    bus.clients.push_back(&clients[k]);
  }
  // Uploads: block, segmented, block with a small block size.
  clients[2].set_block_size(3);
  const SdoMode up_modes[3] = {canopen::kSdoBlock, canopen::kSdoSegmented, canopen::kSdoBlock};
  VectorData got[3];
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(clients[k].start_upload(kDomainIndex, kDomainSub, up_modes[k], got[k].data(), 0xFFFFFFFFu,
                                        bus.now, bus.sink()));
  }
  bus.run();
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(clients[k].result(), canopen::kSdoOk) << k;
    EXPECT_EQ(got[k].bytes, domains[k].content) << k;
  }
  // The transfers really overlapped: frames of all three channels appear
  // before the first channel's last frame.
  size_t last_of_first = 0;
  for (size_t i = 0; i < bus.log.size(); ++i) {
    if (bus.log[i].id == 0x580u + ids[0] || bus.log[i].id == 0x600u + ids[0]) last_of_first = i;
  }
  bool seen[3] = {false, false, false};
  for (size_t i = 0; i < last_of_first; ++i) {
    for (int k = 0; k < 3; ++k) seen[k] = seen[k] || bus.log[i].id == 0x580u + ids[k];
  }
  EXPECT_TRUE(seen[0] && seen[1] && seen[2]);

  // Downloads at once, crosswise data: each server keeps only its own.
  const SdoMode down_modes[3] = {canopen::kSdoSegmented, canopen::kSdoBlock, canopen::kSdoBlock};
  Bytes data[3];
  for (int k = 0; k < 3; ++k) {
    data[k] = pattern(4000 - 7 * static_cast<uint32_t>(k), 99 + static_cast<uint32_t>(k));
    ASSERT_TRUE(clients[k].start_download(kDomainIndex, kDomainSub, down_modes[k], data[k].data(),
                                          static_cast<uint32_t>(data[k].size()), bus.now, bus.sink()));
  }
  bus.run();
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(clients[k].result(), canopen::kSdoOk) << k;
    EXPECT_EQ(domains[k].content, data[k]) << k;
  }
}

}  // namespace
}  // namespace test
}  // namespace mb2co
