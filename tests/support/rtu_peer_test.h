// A GoogleTest fixture for the Modbus peer tests of a program with
// mb2co-node's ready line and control channel (mb2co-node, mb2co-uno): the
// program started with --can none on a pty in a temporary directory, and
// libmodbus as its master. Process: NodeProcess or a class derived from it.
#pragma once
#include <gtest/gtest.h>
#include <poll.h>

#include <string>

#include "node_harness.h"
#include "rtu_frames.h"

namespace mb2co {
namespace test {

template <class Process>
class RtuPeerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(peer_.start({"--can", "none", "--pty", dir_.path("peer.pty")})) << peer_.error();
    ASSERT_EQ(peer_.device(), dir_.path("peer.pty")) << "the ready line names the link";
    ASSERT_TRUE(master_.open(peer_.device())) << master_.error();
    ctx_ = master_.ctx();
    fd_ = master_.fd();
  }
  void TearDown() override {
    master_.close();
    EXPECT_EQ(peer_.stop(), 0) << "exit status after SIGTERM";
  }

  /// A request PDU to slave 1 sent by libmodbus; the response without CRC.
  Bytes raw_transaction(const Bytes& pdu) {
    Bytes rsp = master_.raw_transaction(pdu);
    EXPECT_FALSE(rsp.empty()) << "no response to FC " << int(pdu[0]);
    return rsp;
  }
  uint16_t diag_counter(uint8_t sub) {
    const uint16_t v = master_.diag_counter(sub);
    EXPECT_NE(v, 0xFFFF) << "08/" << int(sub);
    return v;
  }
  /// True when nothing arrives on the port within `window` (the absence of
  /// an answer can only be shown with a bound).
  bool silent_for(std::chrono::milliseconds window) {
    pollfd p{fd_, POLLIN, 0};
    return poll(&p, 1, static_cast<int>(window.count())) == 0;
  }

  TempDir dir_;
  Process peer_;
  ModbusMaster master_;
  modbus_t* ctx_ = nullptr;
  int fd_ = -1;
};

}  // namespace test
}  // namespace mb2co
