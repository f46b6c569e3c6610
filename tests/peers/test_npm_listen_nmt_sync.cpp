// NMT commands and SYNC frames, sent by can-utils' cansend, as npm's canopen
// sees them (ctest peers.npm_listen_nmt_sync, inside run-with-vcan.sh): the
// listen peer is an NMT slave with node id 9 and a SYNC consumer on 80h.
// The same sequence is then sent by mb2co-master's nmt and sync commands.
#include <gtest/gtest.h>

#include "master_cli.h"
#include "npm_peer.h"

namespace mb2co {
namespace test {
namespace {

class NpmListen : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(listener_.start(peer_command({"listen", "--node", "9"}))) << listener_.error();
    ASSERT_TRUE(listener_.wait_prefix("ready node=9", kPeerDeadline)) << listener_.stderr_text();
  }
  /// cansend vcan0 FRAME, then the listener's next `lines` lines must be
  /// exactly `want` (so a line that should not come fails the next check).
  void send_expect(const std::string& frame, const std::vector<std::string>& want) {
    LineChild cansend;
    ASSERT_TRUE(cansend.start({"cansend", "vcan0", frame})) << cansend.error();
    ASSERT_EQ(cansend.wait_exit(kPeerDeadline), 0) << cansend.stderr_text();
    for (const std::string& w : want) {
      std::string line;
      ASSERT_TRUE(listener_.wait_line([](const std::string&) { return true; }, kPeerDeadline, &line))
          << "after " << frame << " no line; wanted '" << w << "'; stderr " << listener_.stderr_text();
      EXPECT_EQ(line, w) << "after " << frame;
    }
  }

  /// mb2co-master ARGS, then the listener's next lines must be exactly `want`.
  void master_expect(const std::vector<std::string>& args, const std::vector<std::string>& want) {
    const MasterRun run = run_master(args, kPeerDeadline);
    ASSERT_EQ(run.exit_code, 0) << run.text() << run.err;
    expect_lines(args.empty() ? "" : args[0] + " " + (args.size() > 1 ? args[1] : ""), want);
  }
  void expect_lines(const std::string& after, const std::vector<std::string>& want) {
    for (const std::string& w : want) {
      std::string line;
      ASSERT_TRUE(listener_.wait_line([](const std::string&) { return true; }, kPeerDeadline, &line))
          << "after " << after << " no line; wanted '" << w << "'; stderr " << listener_.stderr_text();
      EXPECT_EQ(line, w) << "after " << after;
    }
  }

  LineChild listener_;
};

TEST_F(NpmListen, SeesNmtCommandsAndSyncFrames) {
  // Its own start: pre-operational came before the ready line.
  send_expect("080#", {"sync"});  // SYNC without counter
  send_expect("000#0109", {"nmt command=1 node=9", "state operational"});
  send_expect("080#07", {"sync counter=7"});  // SYNC with counter
  // Addressed to another node: seen on the bus, no state change (the next
  // line is the next frame's).
  send_expect("000#0205", {"nmt command=2 node=5"});
  send_expect("080#08", {"sync counter=8"});
  // Broadcast enter pre-operational, then broadcast stop.
  send_expect("000#8000", {"nmt command=128 node=0", "state pre-operational"});
  send_expect("000#0200", {"nmt command=2 node=0", "state stopped"});
  // Stopped: its Sync module no longer consumes SYNC (CiA 301 §7.3.2.2), so
  // after this SYNC the next line is the next NMT command's.
  send_expect("080#09", {});
  send_expect("000#0109", {"nmt command=1 node=9", "state operational"});
  send_expect("080#0A", {"sync counter=10"});
}

TEST_F(NpmListen, SeesMb2coMastersNmtCommandsAndSyncFrames) {
  // SYNC without counter (--overflow 0, the default).
  master_expect({"sync"}, {"sync"});
  master_expect({"nmt", "start", "9"}, {"nmt command=1 node=9", "state operational"});
  // Three SYNCs with a counter that wraps after 2 (CiA 301: 1, 2, 1).
  master_expect({"sync", "--period", "20", "--count", "3", "--overflow", "2"},
                {"sync counter=1", "sync counter=2", "sync counter=1"});
  // Another node: seen, no state change; the next line is the next SYNC's.
  master_expect({"nmt", "stop", "5"}, {"nmt command=2 node=5"});
  master_expect({"sync"}, {"sync"});
  master_expect({"nmt", "preop", "all"}, {"nmt command=128 node=0", "state pre-operational"});
  master_expect({"nmt", "stop", "9"}, {"nmt command=2 node=9", "state stopped"});
  // Stopped: no SYNC consumed, so the next line is the next NMT command's.
  master_expect({"sync"}, {});
  master_expect({"nmt", "start", "all"}, {"nmt command=1 node=0", "state operational"});
  master_expect({"sync", "--cob-id", "0x80"}, {"sync"});
}

}  // namespace
}  // namespace test
}  // namespace mb2co
