// Independent peer: mbpoll (Debian) reads and writes the same registers of
// mb2co-node --can none through every table of the gateway's map.
#include <gtest/gtest.h>

#include "mbpoll_run.h"
#include "node_harness.h"

namespace mb2co {
namespace test {
namespace {

class Mbpoll : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(node_.start({"--can", "none", "--pty", dir_.path("node.pty")})) << node_.error();
  }
  void TearDown() override { EXPECT_EQ(node_.stop(), 0); }

  /// mbpoll once (-1) on slave 1, 0-based references (-0), 8N1 at 115200:
  /// `options`, the device, then `values` to write (none: a read).
  MbpollRun mbpoll(const std::vector<std::string>& options, const std::vector<std::string>& values = {}) {
    std::vector<std::string> argv{MB2CO_MBPOLL, "-m", "rtu", "-b", "115200", "-P", "none",
                                  "-a",         "1",  "-0",  "-1", "-o",     "1"};
    argv.insert(argv.end(), options.begin(), options.end());
    argv.push_back(node_.device());
    argv.insert(argv.end(), values.begin(), values.end());
    return run_mbpoll(argv);
  }
  std::vector<std::string> read(const std::string& table, int ref, int count) {
    const MbpollRun r = mbpoll({"-t", table, "-B", "-r", std::to_string(ref), "-c", std::to_string(count)});
    EXPECT_EQ(r.status, 0) << r.output;
    return r.values;
  }
  void write(const std::string& table, int ref, const std::vector<std::string>& values) {
    const MbpollRun r = mbpoll({"-t", table, "-B", "-r", std::to_string(ref)}, values);
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("Written " + std::to_string(values.size()) + " reference"), std::string::npos)
        << r.output;
  }

  TempDir dir_;
  NodeProcess node_;
};

using Values = std::vector<std::string>;

TEST_F(Mbpoll, ReadsAndWritesTheSameRegisters) {
  write("4", 0, {"1", "1"});  // FC 10: RUN command, lab LED
  EXPECT_EQ(read("4", 0, 2), (Values{"1", "1"}));
  EXPECT_EQ(read("0", 0, 2), (Values{"1", "1"})) << "coils 0-1 are the same OD entries";
  EXPECT_EQ(read("3", 1, 1), (Values{"1"})) << "RUN state";
  EXPECT_EQ(read("1", 3, 1), (Values{"1"})) << "RUN state as a discrete input";
  write("0", 1, {"0"});  // FC 05: lab LED off
  EXPECT_EQ(read("4", 1, 1), (Values{"0"}));
  write("4", 7, {"35"});  // FC 06: debounce
  EXPECT_EQ(read("4", 7, 1), (Values{"35"}));
}

TEST_F(Mbpoll, ThirtyTwoBitEntryIsTwoRegistersHighWordFirst) {
  write("4:int", 9, {"100000"});  // -B: big-endian word order
  EXPECT_EQ(read("4", 9, 2), (Values{"1", "34464"}));
  EXPECT_EQ(read("4:int", 9, 1), (Values{"100000"}));
}

TEST_F(Mbpoll, ExceptionsReported) {
  MbpollRun r = mbpoll({"-t", "4", "-r", "0"}, {"2"});
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("Slave device or server failure"), std::string::npos) << r.output;
  r = mbpoll({"-t", "4", "-r", "20", "-c", "1"});  // past the 20 registers of the map
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("Illegal data address"), std::string::npos) << r.output;
  r = mbpoll({"-u"});  // FC 11 report slave id
  EXPECT_NE(r.output.find("Illegal function"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace test
}  // namespace mb2co
