// mb2co-master against malicious SDO servers (issue 22 item 4): a server
// that keeps answering never keeps the master busy. One RogueServer per
// case (node 5 on vcan0, a thread of this test): a 4 GB size indication
// (segmented and block), segments without end and without a size, more
// bytes than indicated (segmented and block), a typed read of more than
// 64 KiB, a block upload without a size streamed to its --max-bytes, block
// transfers that never get a sub-block through (fast: the repeat bound;
// slow: the timeout from the last progress) and empty segments forever.
// Each case: the documented abort code reaches the server, the documented
// exit status, the end within -t (plus slack) of the server's last progress
// on the monotonic clock, no file left behind, and the master's peak RSS
// within 512 KiB of a plain read's. Then a scan against a node that loses
// a request (asked once more) and a node id that never answers (no abort:
// a probe). Last, a node whose heartbeat says it serves SDO and that loses
// a request (or times out itself) is asked once more, one that never
// answers times out after two asks, a stopped one after one.
// ctest runs this binary inside hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <memory>

#include "master_cli.h"
#include "measured_run.h"
#include "rogue_server.h"

namespace mb2co {
namespace test {
namespace {

using std::chrono::milliseconds;

/// -t of the cases that time out; 5 s where the bound must end it first.
const milliseconds kT{500};
const milliseconds kLongT{5000};
/// User-mode Linux on a busy 2-core host: a few hundred ms per process
/// start, ~0.1 ms per syscall.
const milliseconds kSlack{1500};
/// The master's peak RSS may exceed a plain read's by this much: an upload
/// held in memory (1 MiB in the streaming case) does not fit.
const long kRssSlackKib = 512;

/// A segmented upload segment answering request `r`: 7 bytes, c = 0.
Bytes8 full_segment(const CanFrame& r) {
  return {static_cast<uint8_t>(r.data[0] & 0x10), 1, 2, 3, 4, 5, 6, 7};
}

/// Block segments `first`..`last` (c = 0), 7 bytes each.
std::vector<Bytes8> segments(uint8_t first, uint8_t last) {
  std::vector<Bytes8> v;
  for (unsigned s = first; s <= last; ++s) v.push_back({static_cast<uint8_t>(s), 9, 9, 9, 9, 9, 9, 9});
  return v;
}

bool exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

long ms_between(Clock::time_point from, Clock::time_point to) {
  return static_cast<long>(std::chrono::duration_cast<milliseconds>(to - from).count());
}

class MasterBounds : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // The yardstick: a 4-byte read, answered expedited at once.
    RogueServer s;
    ASSERT_TRUE(s.start([](RogueServer& srv, const CanFrame& r) { srv.send(mux(r, 0x43, 0x12345678)); }))
        << s.error();
    char dir[] = "/tmp/mb2co_bounds_XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    const MeasuredRun run = run_measured({"read", "5", "1000", "0", "u32"}, dir, kVcanDeadline);
    std::system((std::string("rm -rf ") + dir).c_str());
    ASSERT_EQ(run.exit_code, 0) << run.err << run.error;
    ASSERT_EQ(run.out, "0x12345678\n");
    baseline_rss_kib_ = run.max_rss_kib;
    std::printf("baseline: a plain read peaks at %ld KiB RSS\n", baseline_rss_kib_);
  }

  void SetUp() override {
    char dir[] = "/tmp/mb2co_bounds_XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override {
    server_.stop();
    std::system(("rm -rf " + dir_).c_str());
  }

  std::string path(const std::string& name) const { return dir_ + "/" + name; }

  /// Starts the server with `handler`, runs the master with `args` (killed
  /// when it runs `t` + 10 s: the old master never ended), waits for the
  /// abort to reach the server.
  MeasuredRun run(RogueServer::Handler handler, const std::vector<std::string>& args, milliseconds t) {
    EXPECT_TRUE(server_.start(std::move(handler))) << server_.error();
    const MeasuredRun r = run_measured(args, dir_, t + milliseconds(10000));
    EXPECT_TRUE(server_.wait_abort(kSlack)) << "no abort reached the server";
    server_.stop();
    return r;
  }

  /// The documented end: `code` sent to the server, exit `status` with the
  /// abort on stderr, within `t` + slack of the last progress (at least `t`
  /// when it is the timeout), no file left, RSS bounded.
  void expect_end(const MeasuredRun& r, uint32_t code, int status, milliseconds t,
                  const std::string& file = "") {
    char hex[16];
    std::snprintf(hex, sizeof hex, "%08Xh", code);
    EXPECT_EQ(server_.abort_code(), code) << "the server got " << std::hex << server_.abort_code();
    EXPECT_EQ(r.exit_code, status) << r.err << r.error;
    EXPECT_NE(r.err.find(std::string("SDO abort sent ") + hex), std::string::npos) << r.err;
    EXPECT_EQ(server_.frames_after_abort(), 0u) << "the master went on after its abort";
    const long abort_ms = ms_between(server_.progress_at(), server_.abort_at());
    const long exit_ms = ms_between(server_.progress_at(), r.exited_at);
    EXPECT_LE(abort_ms, (t + kSlack).count()) << "abort " << abort_ms << " ms after the last progress";
    EXPECT_LE(exit_ms, (t + kSlack).count()) << "exit " << exit_ms << " ms after the last progress";
    if (code == 0x05040000u) {
      EXPECT_GE(abort_ms, t.count()) << "timed out before -t";
    }
    EXPECT_LE(r.max_rss_kib, baseline_rss_kib_ + kRssSlackKib) << "RSS peak " << r.max_rss_kib << " KiB";
    if (!file.empty()) {
      EXPECT_FALSE(exists(file)) << file;
      EXPECT_FALSE(exists(file + ".part")) << file << ".part";
    }
    std::printf(
        "%s: abort %ld ms, exit %ld ms after the last progress; RSS %ld KiB (read: %ld); %llu frames sent\n",
        hex, abort_ms, exit_ms, r.max_rss_kib, baseline_rss_kib_,
        static_cast<unsigned long long>(server_.frames_sent()));
  }

  /// `scan 5 5` (-t kT) against the server with `handler`; the server is
  /// stopped after every frame the master sent.
  MeasuredRun scan_node_5(RogueServer::Handler handler) {
    EXPECT_TRUE(server_.start(std::move(handler))) << server_.error();
    const MeasuredRun r =
        run_measured({"-t", std::to_string(kT.count()), "scan", "5", "5"}, dir_, kT * 4 + kSlack);
    server_.stop();
    return r;
  }

  static long baseline_rss_kib_;
  RogueServer server_;
  std::string dir_;
};
long MasterBounds::baseline_rss_kib_ = 0;

const std::string kTArg = std::to_string(kT.count());
const std::string kLongTArg = std::to_string(kLongT.count());

TEST_F(MasterBounds, A4GiBSizeIndicationIsRefusedAtOnce) {
  int segment_requests = 0;
  const std::string file = path("big.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0x40) {
          s.progress();
          s.send(mux(q, 0x41, 0xFFFFFFFFu));  // segmented, 4 GiB - 1 indicated
        } else {
          ++segment_requests;
          s.send(full_segment(q));
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file}, kT);
  expect_end(r, 0x05040005u, 1, milliseconds(0), file);
  EXPECT_EQ(segment_requests, 0);
  EXPECT_NE(r.err.find("the object is longer than 16777216 bytes, the most this command takes"),
            std::string::npos)
      << r.err;
}

TEST_F(MasterBounds, A4GiBBlockTransferIsRefusedAtOnce) {
  int starts = 0;
  const std::string file = path("big.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0xA4) {
          s.progress();
          s.send(mux(q, 0xC6, 0xFFFFFFFFu));  // block, CRC, 4 GiB - 1 indicated
        } else if (q.data[0] == 0xA3) {
          ++starts;
          s.send(segments(1, 127));
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file, "--block"}, kT);
  expect_end(r, 0x05040005u, 1, milliseconds(0), file);
  EXPECT_EQ(starts, 0);
}

TEST_F(MasterBounds, SegmentsWithoutEndAndWithoutSizeStopAtMaxBytes) {
  int segments_sent = 0;
  const std::string file = path("endless.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        s.progress();
        if (q.data[0] == 0x40) {
          s.send(mux(q, 0x40));  // segmented, no size
        } else {
          ++segments_sent;
          s.send(full_segment(q));
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file, "--max-bytes", "35000"}, kT);
  expect_end(r, 0x05040005u, 1, milliseconds(0), file);
  EXPECT_EQ(segments_sent, 5001);  // 5000 x 7 = 35000 bytes taken, the next one is beyond
  EXPECT_NE(r.err.find("longer than 35000 bytes"), std::string::npos) << r.err;
}

TEST_F(MasterBounds, ATypedReadTakesAtMost64KiB) {
  int segment_requests = 0;
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0x40) {
          s.progress();
          s.send(mux(q, 0x41, 65537));
        } else {
          ++segment_requests;
          s.send(full_segment(q));
        }
      },
      {"-t", kTArg, "read", "5", "2000", "0", "os"}, kT);
  expect_end(r, 0x05040005u, 1, milliseconds(0));
  EXPECT_EQ(segment_requests, 0);
  EXPECT_NE(r.err.find("longer than 65536 bytes"), std::string::npos) << r.err;
}

TEST_F(MasterBounds, MoreSegmentedBytesThanIndicatedAreAbortedAtOnce) {
  int segments_sent = 0;
  const std::string file = path("more.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        s.progress();
        if (q.data[0] == 0x40) {
          s.send(mux(q, 0x41, 10));
        } else {
          ++segments_sent;
          s.send(full_segment(q));  // c = 0 every time
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file}, kT);
  expect_end(r, 0x06070012u, 1, milliseconds(0), file);
  EXPECT_EQ(segments_sent, 2);  // 14 > 10 bytes
}

TEST_F(MasterBounds, MoreBlockBytesThanIndicatedAreAbortedAtTheSegmentThatShowsThem) {
  int acks = 0;
  const std::string file = path("more.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0xA4) {
          s.progress();
          s.send(mux(q, 0xC6, 10));
        } else if (q.data[0] == 0xA3) {
          s.progress();
          // Two full segments (c = 0), then nothing: the second shows 14
          // bytes of 10. A master that waits for a third segment to store
          // the second one waits into its timeout.
          s.send(segments(1, 2));
        } else if (q.data[0] == 0xA2) {
          ++acks;
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file, "--block"}, kT);
  expect_end(r, 0x06070012u, 1, milliseconds(0), file);
  EXPECT_EQ(acks, 0);
}

TEST_F(MasterBounds, ABlockUploadWithoutSizeStreamsToTheFileUpToMaxBytes) {
  int acks = 0;
  const std::string file = path("stream.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0xA4) {
          s.progress();
          s.send(mux(q, 0xC4));  // block, CRC, no size
          return;
        }
        if (q.data[0] == 0xA2) ++acks;
        if (q.data[0] == 0xA3 || q.data[0] == 0xA2) {
          s.progress();
          s.send(segments(1, 127));  // every sub-block whole, forever
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file, "--block", "--max-bytes", "1048576"}, kT);
  expect_end(r, 0x05040005u, 1, milliseconds(0), file);
  // 1 MiB is 149796 segments and 4 bytes: segment 149797 is beyond, in
  // sub-block 1180 (127 each); the 1179 before it were acknowledged.
  EXPECT_EQ(acks, 1179);
}

TEST_F(MasterBounds, ABlockUploadNeverInSequenceEndsAtTheRepeatBound) {
  int acks = 0;
  const std::string file = path("stuck.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0xA4) {
          s.progress();
          s.send(mux(q, 0xC6, 100000));
          return;
        }
        if (q.data[0] == 0xA2) ++acks;
        if (q.data[0] == 0xA3 || q.data[0] == 0xA2) s.send(segments(2, 127));  // segment 1 never comes
      },
      {"-t", kLongTArg, "upload", "5", "2000", "0", file, "--block"}, kLongT);
  expect_end(r, 0x05040003u, 1, kLongT, file);
  EXPECT_EQ(acks, 8);  // 8 repeats acknowledged (ackseq 0), the 9th sub-block aborted
}

/// A block download server that acknowledges none of a sub-block, after
/// `delay` (0: at once).
RogueServer::Handler acks_nothing(milliseconds delay, int* sub_blocks) {
  auto initiated = std::make_shared<bool>(false);
  return [delay, sub_blocks, initiated](RogueServer& s, const CanFrame& q) {
    if (!*initiated) {  // the initiate: 110 00 cc s 0, size
      *initiated = true;
      s.progress();
      s.send(mux(q, 0xA4, 127));
      return;
    }
    const uint8_t seqno = q.data[0] & 0x7F;
    if (seqno != 127 && (q.data[0] & 0x80) == 0) return;  // not the sub-block's end
    ++*sub_blocks;
    const Bytes8 ack = {0xA2, 0, 127, 0, 0, 0, 0, 0};
    if (delay.count() == 0)
      s.send(ack);
    else
      s.send_later(delay, ack);
  };
}

TEST_F(MasterBounds, ABlockDownloadReAckedWithNothingEndsAtTheRepeatBound) {
  int sub_blocks = 0;
  const std::string file = path("down.bin");
  std::ofstream(file, std::ios::binary) << std::string(1000, 'x');
  const MeasuredRun r = run(acks_nothing(milliseconds(0), &sub_blocks),
                            {"-t", kLongTArg, "download", "5", "2000", "0", file, "--block"}, kLongT);
  expect_end(r, 0x05040003u, 1, kLongT);
  EXPECT_EQ(sub_blocks, 9);  // the first and 8 repeats; the 9th ack of nothing ends it
}

TEST_F(MasterBounds, ASlowBlockDownloadServerWithoutProgressTimesOutAfterT) {
  int sub_blocks = 0;
  const std::string file = path("down.bin");
  std::ofstream(file, std::ios::binary) << std::string(1000, 'x');
  const MeasuredRun r = run(acks_nothing(milliseconds(150), &sub_blocks),
                            {"-t", kTArg, "download", "5", "2000", "0", file, "--block"}, kT);
  expect_end(r, 0x05040000u, 4, kT);
  EXPECT_LE(sub_blocks, 5);  // a sub-block every ~150 ms until -t: fewer than the bound
}

TEST_F(MasterBounds, EmptySegmentsForeverTimeOutAfterT) {
  int segments_sent = 0;
  const std::string file = path("empty.bin");
  const MeasuredRun r = run(
      [&](RogueServer& s, const CanFrame& q) {
        if (q.data[0] == 0x40) {
          s.progress();
          s.send(mux(q, 0x40));
        } else {
          ++segments_sent;
          s.send({static_cast<uint8_t>((q.data[0] & 0x10) | 0x0E), 0, 0, 0, 0, 0, 0, 0});  // n = 7, c = 0
        }
      },
      {"-t", kTArg, "upload", "5", "2000", "0", file}, kT);
  expect_end(r, 0x05040000u, 4, kT, file);
  EXPECT_GT(segments_sent, 1);
}

/// A scan's answers from node 5: 1000h, 1018h/n = n, 1008h "abc"; the
/// first `lost` requests for `lost_index`/`lost_sub` are dropped (each
/// request for it counted in *asked).
RogueServer::Handler loses_requests(uint16_t lost_index, uint8_t lost_sub, int lost, int* asked) {
  return [=](RogueServer& s, const CanFrame& q) {
    if (q.data[0] != 0x40) return;
    const uint16_t index = static_cast<uint16_t>(q.data[1] | q.data[2] << 8);
    const uint8_t sub = q.data[3];
    if (index == lost_index && sub == lost_sub && ++*asked <= lost) return;  // lost in a burst
    if (index == 0x1000) return s.send(mux(q, 0x43, 0x00030191));
    if (index == 0x1018) return s.send(mux(q, 0x43, sub));
    s.send(mux(q, 0x47, 0x00636261));  // 3 bytes: "abc"
  };
}

/// Node 5's line in a scan up to its name.
const char kNode5[] =
    "node 5: device type 0x00030191, vendor 0x00000001, product 0x00000002, revision 0x00000003, "
    "serial 0x00000004, name ";

TEST_F(MasterBounds, AScanAsksOnceMoreForWhatANodeThatAnsweredLost) {
  int asked = 0;
  server_.keep_answering_after_abort();
  const MeasuredRun r = scan_node_5(loses_requests(0x1018, 1, 1, &asked));
  EXPECT_EQ(r.exit_code, 0) << r.err << r.error;
  EXPECT_EQ(r.out, std::string(kNode5) + "\"abc\"\nscan: 1 of 1 node ids answered\n");
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(server_.abort_code(), 0x05040000u) << "the lost read's timeout is sent before it is asked again";
}

TEST_F(MasterBounds, AScanAsksOnlyOnceMoreAndShowsWhatStaysMissing) {
  int asked = 0;
  server_.keep_answering_after_abort();
  const MeasuredRun r = scan_node_5(loses_requests(0x1008, 0, 3, &asked));
  EXPECT_EQ(r.exit_code, 0) << r.err << r.error;
  EXPECT_EQ(r.out, std::string(kNode5) + "\"\"\nscan: 1 of 1 node ids answered\n");
  EXPECT_EQ(asked, 2) << "1008h asked twice, then shown empty";
}

TEST_F(MasterBounds, AScanSendsNoAbortToANodeIdThatNeverAnswered) {
  int asked = 0;
  const MeasuredRun r = scan_node_5(loses_requests(0x1000, 0, 3, &asked));
  EXPECT_EQ(r.exit_code, 4) << r.err << r.error;
  EXPECT_EQ(asked, 1) << "a silent node id is asked once";
  EXPECT_EQ(server_.abort_code(), 0u) << "a probe that nobody answered sent an abort";
}

/// `read 5 2000 0 u8` against a node that answers 7 but loses the first
/// `lost` requests, sending its heartbeat with NMT `state` instead (each
/// request counted in *asked).
RogueServer::Handler loses_while_beating(int lost, uint8_t state, int* asked) {
  return [=](RogueServer& s, const CanFrame& q) {
    if (q.data[0] != 0x40) return;
    if (++*asked <= lost) return s.heartbeat(state);  // lost in its receive buffers, yet there
    s.progress();
    s.send(mux(q, 0x4F, 7));
  };
}

TEST_F(MasterBounds, ARequestLostWhileTheNodeBeatsIsAskedOnceMore) {
  int asked = 0;
  server_.keep_answering_after_abort();
  EXPECT_TRUE(server_.start(loses_while_beating(1, 0x05, &asked))) << server_.error();
  const MeasuredRun r = run_measured({"-t", kTArg, "read", "5", "2000", "0", "u8"}, dir_, kT * 4 + kSlack);
  server_.stop();
  EXPECT_EQ(r.exit_code, 0) << r.err << r.error;
  EXPECT_EQ(r.out, "0x7\n") << r.err;
  EXPECT_EQ(asked, 2);
  EXPECT_EQ(server_.abort_code(), 0x05040000u) << "the timeout's abort goes out before it is asked again";
}

TEST_F(MasterBounds, AServerTimeoutWhileTheNodeBeatsIsAskedOnceMore) {
  // The node's own SDO timeout (it waited for a request that did not
  // come): abort 05040000h from it, its heartbeat operational; then it answers.
  int asked = 0;
  EXPECT_TRUE(server_.start([&asked](RogueServer& s, const CanFrame& q) {
    if (q.data[0] != 0x40) return;
    if (++asked == 1) {
      s.heartbeat(0x05);
      return s.send(mux(q, 0x80, 0x05040000));
    }
    s.send(mux(q, 0x4F, 7));
  })) << server_.error();
  const MeasuredRun r = run_measured({"-t", kTArg, "read", "5", "2000", "0", "u8"}, dir_, kT * 4 + kSlack);
  server_.stop();
  EXPECT_EQ(r.exit_code, 0) << r.err << r.error;
  EXPECT_EQ(r.out, "0x7\n") << r.err;
  EXPECT_EQ(asked, 2);
}

TEST_F(MasterBounds, ANodeThatBeatsButNeverAnswersTimesOutAfterTwoAsks) {
  int asked = 0;
  server_.keep_answering_after_abort();
  const MeasuredRun r =
      run(loses_while_beating(1000, 0x7F, &asked), {"-t", kTArg, "read", "5", "2000", "0", "u8"}, 2 * kT);
  EXPECT_EQ(r.exit_code, 4) << r.err << r.error;
  EXPECT_EQ(asked, 2) << "asked once more, not again";
  EXPECT_NE(r.err.find("SDO abort sent 05040000h"), std::string::npos) << r.err;
  const long exit_ms = ms_between(server_.progress_at(), r.exited_at);
  EXPECT_GE(exit_ms, 2 * kT.count()) << "two timeouts";
  EXPECT_LE(exit_ms, (2 * kT + kSlack).count());
}

TEST_F(MasterBounds, AStoppedNodeIsAskedOnce) {
  int asked = 0;
  const MeasuredRun r =
      run(loses_while_beating(1000, 0x04, &asked), {"-t", kTArg, "read", "5", "2000", "0", "u8"}, kT);
  EXPECT_EQ(r.exit_code, 4) << r.err << r.error;
  EXPECT_EQ(asked, 1) << "a stopped node serves no SDO: its silence is no lost request";
  expect_end(r, 0x05040000u, 4, kT);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
