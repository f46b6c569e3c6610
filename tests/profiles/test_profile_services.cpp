// What a Uno gateway image answers where its profile decides (issue 23's
// decision, shared/profiles/<profile>/mb2co_profile.h), run on the host
// from the very profile's build of the portable code: a line of two
// gateways (tests/gateway/line_harness.h), a Modbus master on station 0.
//   station: every service but FC 2Bh/0Dh (exception 01);
//   network: FC 2Bh/0Dh to the other node, no FC 08 (exception 01), no node
//            guarding (an RTR on 700h+n is not answered; 100Ch/100Dh absent),
//            no 0020h-0023h, no 1011h; heartbeats, PDOs as the station.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "crc/crc16.h"
#include "line_harness.h"
#include "modbus/master_codec.h"
#include "modbus/network_pdu.h"
#include "profiles/profile.h"

namespace mb2co {
namespace test {
namespace {

constexpr uint8_t kAddress = 1;

class ProfileServices : public ::testing::Test {
 protected:
  Line line{2};
  ProfileServices() { line.run_ms(300); }

  // Modbus exception code of the answer to `pdu` (0: a normal answer).
  uint8_t exception_of(const std::vector<uint8_t>& pdu) {
    std::vector<uint8_t> adu{kAddress};
    adu.insert(adu.end(), pdu.begin(), pdu.end());
    uint8_t buf[256];
    std::copy(adu.begin(), adu.end(), buf);
    const uint16_t length = append_crc(buf, static_cast<uint16_t>(adu.size()));
    const std::vector<uint8_t> rsp = line.modbus(0, buf, length);
    EXPECT_GE(rsp.size(), 5u) << "no answer";
    if (rsp.size() < 5u) return 0xFF;
    return (rsp[1] & 0x80u) != 0 ? rsp[2] : 0;
  }
  bool has_entry(uint16_t index, uint8_t sub) {
    return line.gw(0).od().find(index, sub) != canopen::ObjectDictionary::kNoRow;
  }
};

TEST_F(ProfileServices, Fc08DiagnosticsAsTheProfileSays) {
  // 08/00 return query data: echoed where FC 08 is in.
  EXPECT_EQ(exception_of({0x08, 0x00, 0x00, 0x12, 0x34}), profile::kDiagnostics ? 0u : 0x01u);
}

TEST_F(ProfileServices, Fc2BhMei0DhAsTheProfileSays) {
  uint8_t req[64];
  const uint16_t n = modbus::build_net_upload(req, sizeof req, kAddress, 2, 0x1018, 1, 0, 0);
  const std::vector<uint8_t> rsp = line.modbus(0, req, n, 600000);
  ASSERT_GE(rsp.size(), 5u);
  if (profile::kNetwork) {
    modbus::NetResponse r{};
    ASSERT_EQ(modbus::parse_net_response(req, n, rsp.data(), static_cast<uint16_t>(rsp.size()), r),
              modbus::ParseStatus::kOk);
    ASSERT_EQ(r.message.data_length, 4u);  // node 2's vendor id, read over CAN
  } else {
    EXPECT_EQ(rsp[1], 0x2Bu | 0x80u);
    EXPECT_EQ(rsp[2], 0x01u);
  }
}

TEST_F(ProfileServices, GuardingObjectsAndAnswersAsTheProfileSays) {
  EXPECT_EQ(has_entry(0x100C, 0), profile::kGuarding);
  EXPECT_EQ(has_entry(0x100D, 0), profile::kGuarding);
  // Guarding is answered only without a heartbeat: switch node 2's off.
  ASSERT_EQ(line.gw(1).od().write(0x1017, 0, std::vector<uint8_t>{0, 0}.data(), 2), canopen::kSdoOk);
  line.run_ms(10);
  const size_t before = line.log.size();
  CanFrame rtr{};
  rtr.id = 0x702u;
  rtr.flags = CanFrame::kRtr;
  line.gw(1).on_can_frame(rtr, line.now_us);
  line.run_ms(10);
  size_t answers = 0;
  for (size_t i = before; i < line.log.size(); ++i) answers += line.log[i].frame.id == 0x702u ? 1u : 0u;
  EXPECT_EQ(answers, profile::kGuarding ? 1u : 0u);
}

TEST_F(ProfileServices, TypeDescriptionsAsTheProfileSays) {
  for (uint16_t index = 0x0020; index <= 0x0023; ++index)
    EXPECT_EQ(has_entry(index, 0), profile::kTypeDescriptions);
  // Every profile keeps the basic types 0001h-0007h (dummy mapping).
  EXPECT_TRUE(has_entry(0x0007, 0));
  EXPECT_EQ(has_entry(0x1011, 1), profile::kRestoreDefaults);
}

TEST(Profiles, TheUnoImagesAreWhatIssue23Decided) {
  // station: every service the line, the PC plant app and a master use.
  // network: the station plus FC 2Bh/0Dh, without guarding, FC 08, 0020h-0023h
  // and (the budget demanded it after the design steps) 1011h.
  const bool network = std::string(profile::kName) == "network";
  EXPECT_EQ(profile::kNetwork, network);
  EXPECT_EQ(profile::kGuarding, !network);
  EXPECT_EQ(profile::kDiagnostics, !network);
  EXPECT_EQ(profile::kTypeDescriptions, !network);
  EXPECT_EQ(profile::kRestoreDefaults, !network);
  EXPECT_FALSE(profile::kWideTypes);
  // The network image hears every node: its filters stay open.
  EXPECT_EQ(profile::kAcceptanceFilters, !network);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
