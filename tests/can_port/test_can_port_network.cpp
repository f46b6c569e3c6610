// The network gateway image's CAN input (issue 23 item 1), its port code
// built on the host: the port the image picks for the gateway's ranges
// (580h-5FFh and 700h-77Fh are wider than the MCP2515 planner takes) keeps
// the chip's filters open and carries no planner; it hands every frame to
// the gateway, which routes a remote node's SDO response to FC 2Bh/0Dh's
// client and its heartbeat to the network view. Black box from the Modbus
// side and the bus side of the chip model.
#include <gtest/gtest.h>

#include <type_traits>
#include <vector>

#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "uno_can_rig.h"

namespace mb2co {
namespace test {
namespace {

static_assert(profile::kNetwork, "built with the network profile");
static_assert(std::is_same<UnoCanRig::Port, avr::CanPort<false>>::value,
              "the network gateway's ranges are wider than the planner: open filters, no planner");

constexpr uint8_t kAddress = 1;  // the gateway's default Modbus address (2000h/5)
constexpr uint8_t kRemote = 5;   // a node on the bus that is not the gateway (node 1)

TEST(NetworkImagePort, SetsNoFiltersAndTheChipAdmitsEveryFrame) {
  UnoCanRig uno;
  uno.power_on(1);
  EXPECT_EQ(flash_read(&UnoCanRig::Port::kControl).set_filters, nullptr) << "the core has nothing to set";
  CanFrame ext = can_frame(0x123, {1});
  ext.id = 0x1234567;
  ext.flags = CanFrame::kExtended;
  for (const CanFrame& f : {can_frame(0x123, {1}), can_frame(0x585, {0x60}), can_frame(0x7FF, {}), ext}) {
    EXPECT_GE(uno.chip.receive_from_bus(f), 0) << std::hex << f.id;
    uno.pass();  // the port takes it (and the gateway ignores it)
  }
}

TEST(NetworkImagePort, ARemoteSdoResponseReachesTheNetworkService) {
  UnoCanRig uno;
  uno.power_on(1);
  const uint8_t vendor[4] = {0x78, 0x56, 0x34, 0x12};
  int requests = 0;
  int taken = 0;
  size_t seen = uno.chip.bus.size();
  // Node 5 answers the gateway's SDO client: an expedited upload of 1018h/1.
  uno.each_pass = [&] {
    for (; seen < uno.chip.bus.size(); ++seen) {
      const CanFrame f = uno.chip.bus[seen];
      if (f.id != 0x600u + kRemote) continue;
      ++requests;
      EXPECT_EQ(f.data[0], 0x40) << "upload request";
      EXPECT_EQ(f.data[1] | f.data[2] << 8, 0x1018);
      EXPECT_EQ(f.data[3], 1);
      const CanFrame answer =
          can_frame(0x580u + kRemote, {0x43, 0x18, 0x10, 0x01, vendor[0], vendor[1], vendor[2], vendor[3]});
      taken += uno.chip.receive_from_bus(answer) >= 0 ? 1 : 0;
    }
  };
  uint8_t req[64];
  const uint16_t n = modbus::build_net_upload(req, sizeof req, kAddress, kRemote, 0x1018, 1, 0, 0);
  const std::vector<uint8_t> rsp = uno.modbus(req, n, 600000);
  EXPECT_EQ(requests, 1);
  EXPECT_EQ(taken, 1) << "the chip admitted 585h";
  modbus::NetResponse r{};
  ASSERT_EQ(modbus::parse_net_response(req, n, rsp.data(), static_cast<uint16_t>(rsp.size()), r),
            modbus::ParseStatus::kOk)
      << "exception " << int{static_cast<uint8_t>(r.exception)} << " abort " << std::hex << r.abort_code;
  ASSERT_EQ(r.message.data_length, 4u);
  EXPECT_EQ(std::vector<uint8_t>(r.message.data, r.message.data + 4),
            std::vector<uint8_t>(vendor, vendor + 4));
  EXPECT_EQ(r.message.object_size, 4u);
}

TEST(NetworkImagePort, ARemoteNodeThatDoesNotAnswerTimesOut) {
  // The same path without an answer: the client's timeout, not a lost
  // answer, ends it (the answer in the test above is the chip's frame).
  UnoCanRig uno;
  uno.power_on(1);
  uint8_t req[64];
  const uint16_t n = modbus::build_net_upload(req, sizeof req, kAddress, kRemote, 0x1018, 1, 0, 0);
  const std::vector<uint8_t> rsp = uno.modbus(req, n, 2 * gateway::kNetSdoTimeoutUs);
  modbus::NetResponse r{};
  ASSERT_EQ(modbus::parse_net_response(req, n, rsp.data(), static_cast<uint16_t>(rsp.size()), r),
            modbus::ParseStatus::kException);
  EXPECT_EQ(r.abort_code, 0x05040000u);
}

TEST(NetworkImagePort, RemoteHeartbeatsReachTheNetworkView) {
  UnoCanRig uno;
  uno.power_on(1);
  EXPECT_EQ(uno.gw.network().view().find(kRemote), nullptr);
  ASSERT_GE(uno.chip.receive_from_bus(can_frame(0x700u + kRemote, {0x05})), 0);
  uno.run_us(1000);
  const gateway::NetworkView::Entry* e = uno.gw.network().view().find(kRemote);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->state, 0x05) << "operational";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
