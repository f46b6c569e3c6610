// The gateway's side of the platform contract (shared/platform/device_port.h): the
// bit rate of 2000h/2 reaches the port by CanControl::set_bitrate at every
// reset, before the boot-up message and before set_filters; what it must
// receive (its acceptance ranges); frames and controller events through its
// CanInput. Black box: OD writes in, the port's calls and frames out, in one
// log.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "gateway/gateway.h"
#include "profiles/profile.h"

namespace mb2co {
namespace test {
namespace {

std::vector<std::string> g_calls;

bool log_frame(void*, const CanFrame& f) {
  g_calls.push_back("frame " + std::to_string(f.id));
  return true;
}
bool no_serial(void*, const uint8_t*, uint16_t) {
  return true;
}
void log_bitrate(void*, uint16_t kbit) {
  g_calls.push_back("bitrate " + std::to_string(kbit));
}
void log_filters(void*, const CanIdRange*, uint8_t count) {
  g_calls.push_back("filters " + std::to_string(count));
}
const CanControl kControl = {&log_bitrate, &log_filters};

class DevicePort : public ::testing::Test {
 protected:
  void SetUp() override { g_calls.clear(); }
  gateway::Gateway gw{gateway::GatewayPorts{
      CanSink{&log_frame, nullptr}, modbus::ByteSink{&no_serial, nullptr}, nullptr, 115200, &kControl}};
};

TEST_F(DevicePort, ResetSetsBitRateThenFiltersThenSendsBootUp) {
  gw.start(0, 1);
  CanIdRange ranges[canopen::kMaxAcceptanceRanges];
  const uint8_t n = gw.acceptance(ranges);
  EXPECT_EQ(g_calls, (std::vector<std::string>{"bitrate 500", "filters " + std::to_string(n),
                                               "frame " + std::to_string(0x701)}));
}

TEST_F(DevicePort, ANewBitRateReachesThePortAtTheNextResetCommunication) {
  gw.start(0, 1);
  g_calls.clear();
  const uint8_t kbit250[2] = {250, 0};
  ASSERT_EQ(gw.od().write(0x2000, 2, kbit250, 2), canopen::kSdoOk);
  gw.process(1000, 0);
  EXPECT_EQ(g_calls, std::vector<std::string>{}) << "stored, not applied yet";
  const uint8_t reset_comm = 1;
  ASSERT_EQ(gw.od().write(0x2001, 0, &reset_comm, 1), canopen::kSdoOk);
  gw.process(2000, 0);
  ASSERT_GE(g_calls.size(), 3u);
  EXPECT_EQ(g_calls[0], "bitrate 250");
  EXPECT_EQ(g_calls[2], "frame " + std::to_string(0x701));
}

// What the gateway must receive: its node's ids, and the network service's
// ranges where the profile has FC 2Bh/0Dh (every SDO response, every
// heartbeat), handed to the port as they are.
TEST_F(DevicePort, AcceptanceIsTheNodesIdsAndTheNetworkServicesRanges) {
  gw.start(0, 1);
  CanIdRange ranges[canopen::kMaxAcceptanceRanges];
  const uint8_t n = gw.acceptance(ranges);
  bool sdo_request = false, sdo_responses = false, heartbeats = false;
  for (uint8_t i = 0; i < n; ++i) {
    sdo_request |= ranges[i].id == 0x601 && ranges[i].mask == kCanRangeExact;
    sdo_responses |= ranges[i].id == 0x580 && ranges[i].mask == 0x780;
    heartbeats |= ranges[i].id == 0x700 && ranges[i].mask == 0x780;
  }
  EXPECT_TRUE(sdo_request);
  EXPECT_EQ(sdo_responses, profile::kNetwork);
  EXPECT_EQ(heartbeats, profile::kNetwork);
  EXPECT_EQ(gateway::Gateway::kWidestRange > 1, profile::kNetwork || profile::kTpdoRtr)
      << "a port can plan single ids only";
}

// The gateway as a port's device: frames to the node (and the network
// service), the controller's events to the node's EMCY policy.
TEST_F(DevicePort, CanInputRoutesFramesAndControllerEvents) {
  gw.start(0, 1);
  gw.process(1000, 0);  // self-start: operational
  ASSERT_EQ(gw.node().nmt_state(), canopen::kNmtOperational);
  const CanInput in = gw.can_input();
  ASSERT_NE(in.controller_state, nullptr);
  in.controller_state(in.ctx, kControllerRxOverflow, false, 2000);
  EXPECT_TRUE(gw.node().emcy().active(0x8110));
  CanFrame stop{};
  stop.id = 0x000;
  stop.dlc = 2;
  stop.data[0] = 0x02;  // stop
  stop.data[1] = 1;
  in.receive(in.ctx, stop, 3000);
  EXPECT_EQ(gw.node().nmt_state(), canopen::kNmtStopped);
}

/// The boot-up and heartbeat frames (700h-77Fh) among the port's calls (the
/// self-starting station's TPDOs follow its boot-up).
std::vector<std::string> frames_of(const std::vector<std::string>& calls) {
  std::vector<std::string> frames;
  for (const std::string& c : calls) {
    if (c.rfind("frame ", 0) != 0) continue;
    const int id = std::stoi(c.substr(6));
    if (id >= 0x700 && id <= 0x77F) frames.push_back(c);
  }
  return frames;
}

// Issue 22 item 2: an id written (2000h/1 = 9) and not saved is pending. A
// reset node restores the saved id (none saved: the power-on id 5), so its one
// boot-up leaves on 705h: no phantom node 9 announced first. A reset
// communication takes the pending id: one boot-up, on 709h.
TEST_F(DevicePort, AResetNodeWithAnUnsavedIdSendsOneBootUpOnTheIdInForce) {
  gw.start(0, 5);
  g_calls.clear();
  const uint8_t id9 = 9;
  ASSERT_EQ(gw.od().write(0x2000, 1, &id9, 1), canopen::kSdoOk);
  const uint8_t reset_node = 2;
  ASSERT_EQ(gw.od().write(0x2001, 0, &reset_node, 1), canopen::kSdoOk);
  gw.process(1000, 0);
  gw.process(2000, 0);
  EXPECT_EQ(frames_of(g_calls), std::vector<std::string>{"frame " + std::to_string(0x705)});
  EXPECT_EQ(gw.node_id(), 5);

  g_calls.clear();
  ASSERT_EQ(gw.od().write(0x2000, 1, &id9, 1), canopen::kSdoOk);
  const uint8_t reset_comm = 1;
  ASSERT_EQ(gw.od().write(0x2001, 0, &reset_comm, 1), canopen::kSdoOk);
  gw.process(3000, 0);
  gw.process(4000, 0);
  EXPECT_EQ(frames_of(g_calls), std::vector<std::string>{"frame " + std::to_string(0x709)});
  EXPECT_EQ(gw.node_id(), 9);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
