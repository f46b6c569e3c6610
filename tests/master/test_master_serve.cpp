// mb2co-master serve on vcan0 against mb2co-node (nodes 3 and 4), with a
// CiA 309-3 client that is not ours (serve_client.py: Python's sockets) on
// the local socket and on TCP: every command and its answer, two clients at
// once, bad input (an overlong line, binary garbage, a half line), the
// connection limit, the idle timeout, node states and EMCYs as they come,
// and a client killed in the middle of a block upload (a stalling server
// of this test as node 5: the abort reaches it at once, not after the SDO
// timeout, and the other client goes on). ctest runs this binary inside
// hil/uml/run-with-vcan.sh.
#include <gtest/gtest.h>
#include <signal.h>

#include <condition_variable>
#include <mutex>

#include "node_harness.h"
#include "rogue_server.h"
#include "serve_harness.h"

namespace mb2co {
namespace test {
namespace {

using std::chrono::milliseconds;

bool start_node(NodeProcess* node, TempDir* dir, int id) {
  return node->start(
      {"--can", "vcan0", "--node-id", std::to_string(id), "--pty", dir->path("st" + std::to_string(id))});
}

class MasterServe : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    for (int id = 3; id <= 4; ++id) {
      nodes_[id] = new NodeProcess;
      ASSERT_TRUE(start_node(nodes_[id], dir_, id)) << nodes_[id]->error();
    }
  }
  static void TearDownTestSuite() {
    for (NodeProcess*& n : nodes_) {
      delete n;
      n = nullptr;
    }
    delete dir_;
  }
  void TearDown() override {
    if (serve_.child.pid() > 0) {
      EXPECT_EQ(serve_.stop(), 0) << serve_.child.stderr_text();
    }
  }
  void start_serve(const std::string& listen, const std::vector<std::string>& args = {}) {
    ASSERT_TRUE(serve_.start(listen, args)) << serve_.error();
  }
  std::string local() const { return "unix:" + dir_->path("S"); }

  /// Asks every step in turn: the answer must be `want` exactly.
  static void expect_answers(ServeClient& c, const std::vector<std::pair<std::string, std::string>>& steps) {
    for (const auto& s : steps) EXPECT_EQ(c.ask(s.first), s.second) << s.first;
  }
  /// Every command of the set, on a fresh connection to `where`.
  static void every_command(const std::string& where);

  static TempDir* dir_;
  static NodeProcess* nodes_[5];
  ServeProcess serve_;
};
TempDir* MasterServe::dir_ = nullptr;
NodeProcess* MasterServe::nodes_[5] = {};

void MasterServe::every_command(const std::string& where) {
  ServeClient c;
  ASSERT_TRUE(c.open(where));
  // No node in the line and none set yet; then every type both ways.
  expect_answers(c,
                 {
                     {"[1] read 0x1000 0 x32", "[1] ERROR:105 #No default node set."},
                     {"[2] 3 read 0x1000 0 x32", "[2] 0x00030191"},
                     {"[3] 3 r 0x1000 0", "[3] 91 01 03 00"},  // no TYPE: hex
                     {"[4] 3 READ 0x1008 0 vs", "[4] \"mb2co gateway\""},
                     {"[5] 3 write 0x1017 0 u16 250", "[5] OK"},
                     {"[6] 3 read 0x1017 0 u16", "[6] 250"},
                     {"[7] 3 w 0x1017 0 i16 100", "[7] OK"},
                     {"[8] 3 r 0x1017 0 x16", "[8] 0x0064"},
                     {"[9] 3 w 0x2500 1 r32 -2.5", "[9] OK"},
                     {"[10] 3 r 0x2500 1 r32", "[10] -2.5"},
                     {"[11] 3 w 0x1F50 1 i32 -7", "[11] OK"},  // the domain takes any bytes
                     {"[12] 3 r 0x1F50 1 i32", "[12] -7"},
                     {"[13] 3 r 0x1F50 1 u32", "[13] 4294967289"},
                     {"[14] 3 w 0x2500 2 u64 18446744073709551615", "[14] OK"},
                     {"[15] 3 r 0x2500 2 i64", "[15] -1"},
                     {"[16] 3 w 0x2500 2 r64 0.125", "[16] OK"},
                     {"[17] 3 r 0x2500 2 r64", "[17] 0.125"},
                     {"[18] 3 w 0x2500 2 x64 0x1122334455667788", "[18] OK"},
                     {"[19] 3 r 0x2500 2 x64", "[19] 0x1122334455667788"},
                     {"[20] 3 w 0x1F50 1 i64 -9223372036854775808", "[20] OK"},
                     {"[21] 3 r 0x1F50 1 u64", "[21] 9223372036854775808"},
                     {"[22] 3 w 0x6200 1 b 1", "[22] OK"},
                     {"[23] 3 r 0x6200 1 b", "[23] 1"},
                     {"[24] 3 w 0x6200 1 i8 0", "[24] OK"},
                     {"[25] 3 r 0x6200 1 u8", "[25] 0"},
                     {"[26] 3 w 0x6200 1 x8 0x01", "[26] OK"},
                     {"[27] 3 r 0x6200 1 x8", "[27] 0x01"},
                     {"[28] 3 w 0x1F50 1 d TWFu", "[28] OK"},
                     {"[29] 3 r 0x1F50 1 d", "[29] TWFu"},
                     {"[30] 3 r 0x1F50 1 os", "[30] TWFu"},
                     {"[31] 3 r 0x1F50 1 us", "[31] TWFu"},
                     {"[32] 3 r 0x1F50 1 hex", "[32] 4D 61 6E"},
                     {"[33] 3 w 0x1F50 1 hex 01 0203", "[33] OK"},
                     {"[34] 3 r 0x1F50 1 d", "[34] AQID"},
                     {"[35] 3 w 0x1F50 1 vs \"two \"\"words\"\"\"", "[35] OK"},
                     {"[36] 3 r 0x1F50 1 vs", "[36] \"two \"\"words\"\"\""},
                     // The node's refusals as CiA 301 names them; ours as CiA 309-3 numbers them.
                     {"[37] 3 read 0x9999 0 u8",
                      "[37] ERROR:0x06020000 #object does not exist in the object dictionary"},
                     {"[38] 3 w 0x1008 0 vs x", "[38] ERROR:0x06010002 #attempt to write a read only object"},
                     {"[39] 3 read 0x1017 0 u24", "[39] ERROR:101 #Syntax error."},
                     {"[40] 3 write 0x1017 0 u16 65536", "[40] ERROR:101 #Syntax error."},
                     {"[41] 200 start", "[41] ERROR:107 #Unsupported node."},
                     {"[42] 0 read 0x1000 0", "[42] ERROR:107 #Unsupported node."},
                     {"[43] 2 3 start", "[43] ERROR:106 #Unsupported net."},
                     {"[44] lss_store", "[44] ERROR:100 #Request not supported."},
                     // Settings: this connection's defaults.
                     {"[45] set network 1", "[45] OK"},
                     {"[46] set network 2", "[46] ERROR:106 #Unsupported net."},
                     {"[47] set node 4", "[47] OK"},
                     {"[48] r 0x1000 0 x32", "[48] 0x00030191"},
                     {"[49] 1 4 r 0x1017 0 u16", "[49] 100"},
                 });
  // NMT to node 4: stopped, it answers no SDO (our client's timeout, short
  // now); pre-operational, it does again; then every node started.
  expect_answers(c, {
                        {"[50] set sdo_timeout 300", "[50] OK"},
                        {"[51] 4 stop", "[51] OK"},
                        {"[52] r 0x1000 0 x32", "[52] ERROR:0x05040000 #SDO protocol timed out"},
                        {"[53] 4 preop", "[53] OK"},
                        {"[54] r 0x1000 0 x32", "[54] 0x00030191"},
                        {"[55] 4 preoperational", "[55] OK"},
                        {"[56] 0 start", "[56] OK"},
                        {"[57] all start", "[57] OK"},
                        {"[58] 4 reset comm", "[58] OK"},
                        {"[59] set sdo_timeout 5000", "[59] OK"},
                        {"[60] 3 r 0x1000 0 x32", "[60] 0x00030191"},
                        {"[61] 4 reset communication", "[61] OK"},
                        {"[62] 3 start", "[62] OK"},
                    });
  // Block transfer: a 3-byte read, a 40-byte write (block: above 21
  // bytes), read back block-wise.
  expect_answers(
      c, {
             {"[63] set sdo_block 1", "[63] OK"},
             {"[64] 3 r 0x1017 0 u16", "[64] 100"},
             {"[65] 3 w 0x1F50 1 d AAECAwQFBgcICQoLDA0ODxAREhMUFRYXGBkaGxwdHh8gISIjJCUmJw==", "[65] OK"},
             {"[66] 3 r 0x1F50 1 d", "[66] AAECAwQFBgcICQoLDA0ODxAREhMUFRYXGBkaGxwdHh8gISIjJCUmJw=="},
             {"[67] set sdo_block 0", "[67] OK"},
         });
  // Comments, CR LF, blank lines: answered as CANopenNode answers them.
  EXPECT_EQ(c.ask("!raw 5b36385d2033207220307831303137203020753136202320636f6d6d656e740d0a"), "[68] 100");
  EXPECT_EQ(c.ask("# only a comment"), "");
  EXPECT_EQ(c.ask(""), "");
  std::string info = c.ask("[69] info");
  EXPECT_EQ(info.rfind("[69] mb2co-master ", 0), 0u) << info;
  EXPECT_NE(info.find("serve: net 1, SocketCAN vcan0, 1 of 8 clients, sdo_timeout 5000 ms, sdo_block 0"),
            std::string::npos)
      << info;
  // help: lines without a sequence number, the last ends the answer.
  ASSERT_TRUE(c.send("[70] help"));
  std::string line;
  int help_lines = 0;
  while ((line = c.next()).find("answers come in the order of the requests.") == std::string::npos) {
    ASSERT_NE(line, "eof");
    ASSERT_LT(++help_lines, 40);
  }
  EXPECT_GT(help_lines, 10);
  ASSERT_TRUE(c.send("[71] help datatype"));
  while ((line = c.next()).rfind("hex ", 0) != 0) ASSERT_NE(line, "eof");
  EXPECT_EQ(c.ask("[72] 3 r 0x1017 0 u16"), "[72] 100") << "the connection goes on after help";
  ASSERT_TRUE(c.send("!shutdown"));
  EXPECT_EQ(c.next(), "eof");
}

TEST_F(MasterServe, EveryCommandOnTheLocalSocket) {
  start_serve(local());
  EXPECT_EQ(serve_.where(), local());
  every_command(serve_.where());
}

TEST_F(MasterServe, EveryCommandOverTcpOnLocalhost) {
  start_serve("tcp:0");  // the kernel chooses the port; 127.0.0.1 unless told
  ASSERT_EQ(serve_.where().rfind("tcp:127.0.0.1:", 0), 0u) << serve_.where();
  every_command(serve_.where());
}

TEST_F(MasterServe, TwoClientsAtOnceEachGetTheirAnswersInTheirOrder) {
  start_serve(local());
  ServeClient a, b;
  ASSERT_TRUE(a.open(serve_.where()));
  ASSERT_TRUE(b.open(serve_.where()));
  // Both send 20 requests without waiting: a to node 3 and 4 in turn, b to
  // node 4 and 3, b also writing what a reads.
  for (int i = 1; i <= 20; ++i) {
    const std::string seq = "[" + std::to_string(i) + "] ";
    ASSERT_TRUE(a.send(seq + (i % 2 ? "3" : "4") + " r 0x1000 0 x32"));
    ASSERT_TRUE(b.send(seq + (i % 2 ? "4" : "3") + " w 0x2500 1 u32 " + std::to_string(i)));
  }
  for (int i = 1; i <= 20; ++i) {
    const std::string seq = "[" + std::to_string(i) + "] ";
    EXPECT_EQ(a.next(), seq + "0x00030191");
    EXPECT_EQ(b.next(), seq + "OK");
  }
  // The last writes: 20 to node 3, 19 to node 4.
  EXPECT_EQ(a.ask("[21] 3 r 0x2500 1 u32"), "[21] 20");
  EXPECT_EQ(b.ask("[21] 4 r 0x2500 1 u32"), "[21] 19");
}

TEST_F(MasterServe, BadInputGetsItsAnswerAndDisturbsNoOtherClient) {
  start_serve(local());
  ServeClient bad, good;
  ASSERT_TRUE(bad.open(serve_.where()));
  ASSERT_TRUE(good.open(serve_.where()));
  EXPECT_EQ(bad.ask("[1] 3 r 0x1017 0 u16"), "[1] 100");
  // A line longer than the 256 KiB a request may have: ERROR:600 with its
  // sequence number, the rest of the line dropped, the connection goes on.
  EXPECT_EQ(bad.ask("!long 300000 [2] 3 w 0x1F50 1 hex "), "[2] ERROR:600 #Running out of memory.");
  EXPECT_EQ(good.ask("[1] 3 r 0x1017 0 u16"), "[1] 100");
  // Binary garbage: separators only is an empty line; with printable
  // bytes but no [SEQ], ERROR:101 with the last sequence number.
  EXPECT_EQ(bad.ask("!raw 00fffe800d0a"), "");
  EXPECT_EQ(bad.ask("!raw 0102414243ff0a"), "[2] ERROR:101 #Syntax error.");
  EXPECT_EQ(bad.ask("[3] 3 r 0x1017 0 u16"), "[3] 100");
  EXPECT_EQ(good.ask("[2] 4 r 0x1017 0 u16"), "[2] 100");
  // A half line, then the end of input: ERROR:101, then the connection closes.
  ASSERT_TRUE(bad.send("!raw 5b345d20332072203078313031"));
  ASSERT_TRUE(bad.send("!shutdown"));
  EXPECT_EQ(bad.next(), "[4] ERROR:101 #Syntax error.");
  EXPECT_EQ(bad.next(), "eof");
  EXPECT_TRUE(serve_.says("closed: end of input, every answer sent"));
  EXPECT_EQ(good.ask("[3] 3 r 0x1017 0 u16"), "[3] 100");
}

TEST_F(MasterServe, TheConnectionLimitRefusesOneMoreWithALine) {
  start_serve(local(), {"--max-clients", "2"});
  ServeClient a, b, c, d;
  ASSERT_TRUE(a.open(serve_.where()));
  ASSERT_TRUE(b.open(serve_.where()));
  EXPECT_TRUE(serve_.says("connected (2 of 2)"));
  ASSERT_TRUE(c.open(serve_.where()));
  EXPECT_EQ(c.next(), "[0] ERROR:102 #Request not processed due to internal state.");
  EXPECT_EQ(c.next(), "eof");
  EXPECT_TRUE(serve_.says("connection refused: 2 clients already (--max-clients)"));
  EXPECT_EQ(b.ask("[1] 3 r 0x1017 0 u16"), "[1] 100");
  ASSERT_TRUE(a.send("!close"));
  EXPECT_TRUE(serve_.says("closed: gone"));
  ASSERT_TRUE(d.open(serve_.where()));
  EXPECT_EQ(d.ask("[1] 4 r 0x1017 0 u16"), "[1] 100");
}

TEST_F(MasterServe, ASilentClientIsClosedAfterTheIdleTimeout) {
  start_serve(local(), {"-T", "300"});
  ServeClient quiet, busy;
  ASSERT_TRUE(quiet.open(serve_.where()));
  ASSERT_TRUE(busy.open(serve_.where()));
  EXPECT_EQ(busy.ask("[1] 3 r 0x1017 0 u16"), "[1] 100");
  EXPECT_EQ(quiet.next(), "eof");
  EXPECT_TRUE(serve_.says("closed: idle for 300 ms"));
}

TEST_F(MasterServe, NodeStatesAndEmcysAsTheyCome) {
  start_serve(local(), {"--heartbeat", "400"});
  ServeClient watcher, commander;
  ASSERT_TRUE(watcher.open(serve_.where()));
  ASSERT_TRUE(commander.open(serve_.where()));
  EXPECT_EQ(watcher.ask("[1] set events 1"), "[1] OK");
  const auto sees = [&watcher](const std::string& text) {
    return watcher.child.wait_line([&](const std::string& l) { return l.find(text) != std::string::npos; },
                                   kVcanDeadline);
  };
  EXPECT_EQ(commander.ask("[1] 4 stop"), "[1] OK");
  EXPECT_TRUE(sees("CANopen Remote node ID = 0x04 (index = 3): NMT state changed to: \"stopped\" (4)"));
  EXPECT_EQ(commander.ask("[2] 4 start"), "[2] OK");
  EXPECT_TRUE(sees("CANopen Remote node ID = 0x04 (index = 3): NMT state changed to: \"operational\" (5)"));
  // An RPDO shorter than its mapping (RPDO1 of node 3 = TPDO1 of station 2):
  // node 3 answers with EMCY 8210h (PDO length error).
  LineChild send;
  ASSERT_TRUE(send.start({"cansend", "vcan0", "182#01"}));
  ASSERT_EQ(send.wait_exit(kVcanDeadline), 0);
  EXPECT_TRUE(sees("CANopen Emergency message from node 0x03: errorCode=0x8210, errorRegister=0x11"));
  // A node that boots, then dies without a word: lost after the consumer time.
  NodeProcess six;
  ASSERT_TRUE(start_node(&six, dir_, 6)) << six.error();
  EXPECT_TRUE(sees("node ID = 0x06 (index = 5): NMT state changed to: \"initializing\" (0)"));
  EXPECT_TRUE(sees("node ID = 0x06 (index = 5): NMT state changed to: \"operational\" (5)"));
  ASSERT_TRUE(six.child.signal(SIGKILL));
  EXPECT_TRUE(sees("node ID = 0x06 (index = 5): NMT state changed to: \"unknown\" (-1)"));
  // The same lines in `log`, for a client that did not ask for them: one
  // that connects now finds what came before in its first log.
  ServeClient later;
  ASSERT_TRUE(later.open(serve_.where()));
  ASSERT_TRUE(later.send("[1] log"));
  bool stopped = false;
  std::string line;
  while ((line = later.next()).find("\"unknown\" (-1)") == std::string::npos) {
    ASSERT_NE(line, "eof");
    stopped =
        stopped || line.find("0x04 (index = 3): NMT state changed to: \"stopped\"") != std::string::npos;
  }
  EXPECT_TRUE(stopped);
  EXPECT_EQ(later.ask("[2] log"), "") << "each event once";
  EXPECT_TRUE(serve_.says("\"unknown\" (-1)")) << "and on serve's own output";
}

TEST_F(MasterServe, ThroughAGatewayOnItsSerialLine) {
  // No CAN socket of its own: node 3 is the gateway, reached over its pty
  // (FC 2Bh/0Dh); the worker thread carries one request at a time.
  ASSERT_TRUE(serve_.start(local(), {}, {"-t", "5000", "--via-modbus", nodes_[3]->device() + ":1"}))
      << serve_.error();
  ServeClient c;
  ASSERT_TRUE(c.open(serve_.where()));
  // Pipelined: answered in order all the same.
  ASSERT_TRUE(c.send("[1] 4 r 0x1017 0 u16"));
  ASSERT_TRUE(c.send("[2] 3 r 0x1000 0 x32"));
  ASSERT_TRUE(c.send("[3] 4 w 0x2500 1 r32 1.5"));
  ASSERT_TRUE(c.send("[4] 4 r 0x2500 1 r32"));
  EXPECT_EQ(c.next(), "[1] 100");
  EXPECT_EQ(c.next(), "[2] 0x00030191");
  EXPECT_EQ(c.next(), "[3] OK");
  EXPECT_EQ(c.next(), "[4] 1.5");
  expect_answers(
      c, {
             {"[5] 4 r 0x9999 0 u8", "[5] ERROR:0x06020000 #object does not exist in the object dictionary"},
             {"[6] 4 start", "[6] OK"},
             // The gateway's SDO client runs the transfer: neither setting reaches it.
             {"[7] set sdo_block 1", "[7] ERROR:100 #Request not supported."},
             {"[8] set sdo_timeout 100", "[8] ERROR:100 #Request not supported."},
         });
  const std::string info = c.ask("[9] info");
  EXPECT_NE(info.find("serve: net 1, gateway " + nodes_[3]->device() + ":1, 1 of 8 clients"),
            std::string::npos)
      << info;
}

/// Node 5 of this test: answers a block upload's first 3 segments, then
/// nothing (a transfer that would wait for the SDO timeout), and an
/// expedited upload with 12345678h.
class StallingServer {
 public:
  bool start() {
    return server.start([this](RogueServer& s, const CanFrame& q) {
      if (q.data[0] == 0x40) s.send(mux(q, 0x43, 0x12345678));
      if (q.data[0] == 0xA4) s.send(mux(q, 0xC6, 1000));  // block, CRC, 1000 bytes
      if (q.data[0] == 0xA3) {
        s.send(
            {Bytes8{1, 1, 1, 1, 1, 1, 1, 1}, Bytes8{2, 2, 2, 2, 2, 2, 2, 2}, Bytes8{3, 3, 3, 3, 3, 3, 3, 3}});
        std::lock_guard<std::mutex> lock(mutex);
        streaming = true;
        changed.notify_all();
      }
    });
  }
  bool wait_streaming() {
    std::unique_lock<std::mutex> lock(mutex);
    return changed.wait_for(lock, kVcanDeadline, [this] { return streaming; });
  }
  RogueServer server;
  std::mutex mutex;
  std::condition_variable changed;
  bool streaming = false;
};

TEST_F(MasterServe, AClientKilledInTheMiddleOfABlockUploadHasItAbortedAtOnce) {
  StallingServer node5;
  ASSERT_TRUE(node5.start()) << node5.server.error();
  start_serve(local());
  ServeClient killed, other;
  ASSERT_TRUE(killed.open(serve_.where()));
  ASSERT_TRUE(other.open(serve_.where()));
  EXPECT_EQ(killed.ask("[1] set sdo_block 1"), "[1] OK");
  EXPECT_EQ(killed.ask("[2] set sdo_timeout 30000"), "[2] OK");
  ASSERT_TRUE(killed.send("[3] 5 r 0x2000 0 d"));
  ASSERT_TRUE(node5.wait_streaming());
  // Node 5 now waits, and so would the transfer, for 30 s.
  const auto killed_at = Clock::now();
  ASSERT_TRUE(killed.child.signal(SIGKILL));
  ASSERT_TRUE(node5.server.wait_abort(milliseconds(10000))) << "no abort: the transfer waits for its timeout";
  EXPECT_EQ(node5.server.abort_code(), 0x08000020u) << "data cannot be transferred to the application";
  EXPECT_LT(node5.server.abort_at() - killed_at, std::chrono::seconds(10));
  EXPECT_TRUE(serve_.says("closed: gone (1 requests cancelled)"));
  node5.server.stop();
  // The other client goes on, with node 5 too (answering again).
  EXPECT_EQ(other.ask("[1] 3 r 0x1017 0 u16"), "[1] 100");
  StallingServer again;
  ASSERT_TRUE(again.start()) << again.server.error();
  EXPECT_EQ(other.ask("[2] 5 r 0x2000 0 x32"), "[2] 0x12345678");
}

TEST_F(MasterServe, AClientKilledOverTcpDisturbsNoOther) {
  // Over TCP a killed client looks like one that only ended its input (a
  // FIN either way): its block upload runs to its end, the answer goes
  // nowhere, and the connection closes; the other client is served all along.
  start_serve("tcp:0");
  ServeClient killed, other;
  ASSERT_TRUE(killed.open(serve_.where()));
  ASSERT_TRUE(other.open(serve_.where()));
  EXPECT_EQ(killed.ask("[1] set sdo_block 1"), "[1] OK");
  std::string big = "[2] 3 w 0x1F50 1 hex";
  for (int i = 0; i < 60000; ++i) big += " A5";
  EXPECT_EQ(killed.ask(big), "[2] OK");
  ASSERT_TRUE(killed.send("[3] 3 r 0x1F50 1 d"));
  EXPECT_TRUE(serve_.says("client 1 connected"));
  ASSERT_TRUE(killed.child.signal(SIGKILL));
  for (int i = 1; i <= 5; ++i)
    EXPECT_EQ(other.ask("[" + std::to_string(i) + "] 4 r 0x1017 0 u16"), "[" + std::to_string(i) + "] 100");
  EXPECT_TRUE(serve_.says("client 1 closed"));
  EXPECT_EQ(other.ask("[6] 3 r 0x1017 0 u16"), "[6] 100");
}

}  // namespace
}  // namespace test
}  // namespace mb2co
