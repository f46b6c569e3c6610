// Issue 23 "must show": an FC 2Bh client that is not ours, written from
// docs/gateway-network.md, through the Uno network image to remote nodes on
// vcan0 (ctest runs this binary inside hil/uml/run-with-vcan.sh). The client
// is the page's own Python with python3-pymodbus (pymodbus_network_peer.py
// takes it from the page as written and holds the assertions); this file
// only sets up the line it talks to:
//   * the gateway, node 1 (network_gateway.h: mb2co-uno --image network),
//   * node 2, an mb2co-node,
//   * node 20h, the simulated I/O node (mb2co-uno --image ionode, a fresh
//     board),
// and no node 9.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "network_gateway.h"
#include "node_harness.h"
#include "uno_harness.h"

namespace mb2co {
namespace test {
namespace {

constexpr auto kStartDeadline = 60s;  // bounds a failure only (user-mode Linux is slow)
constexpr auto kPeerDeadline = 300s;

TEST(UnoNetworkPymodbus, TheDocsClientReachesTheRemoteNodesThroughTheGateway) {
  TempDir dir;
  std::string error;
  std::unique_ptr<NodeProcess> gateway = start_network_gateway(dir.path("gw.pty"), kStartDeadline, &error);
  ASSERT_NE(gateway, nullptr) << error;
  NodeProcess remote;
  ASSERT_TRUE(
      remote.start({"--can", "vcan0", "--node-id", "2", "--stations", "2", "--pty", dir.path("remote.pty")},
                   kStartDeadline))
      << "mb2co-node: " << remote.error();
  UnoProcess ionode;
  ASSERT_TRUE(ionode.start_command({uno_program(), "--image", "ionode", "--can", "vcan0", "--eeprom",
                                    dir.path("ionode.eeprom"), "--pty", dir.path("ionode.pty")},
                                   kStartDeadline))
      << "mb2co-uno --image ionode: " << ionode.error();
  std::printf("gateway under test: %s\n", network_gateway_name());

  LineChild peer;
  ASSERT_TRUE(
      peer.start({"/usr/bin/python3", MB2CO_PYMODBUS_PEER, MB2CO_GATEWAY_NETWORK_DOC, gateway->device()}))
      << peer.error();
  const int exit_code = peer.wait_exit(kPeerDeadline);
  // unittest reports on stderr: each test and every failure's assertion.
  std::printf("%s", peer.stderr_text().c_str());
  EXPECT_EQ(exit_code, 0) << "the pymodbus client of docs/gateway-network.md failed (its report above)";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
