// A handler per OD entry on the gateway (issue 26 item 2): each write reaches
// the handler its entry names (the node's for 2000h/1-2 and 2001h, the
// gateway's for 2100h/1, the register bank's for 2400h-2403h), the check
// step of a request of several entries (apply false) carries nothing out,
// and the node's one policy of the own node id and bit rate holds on the
// gateway as on the I/O node (tests/canopen/test_ionode_config.cpp).
// Black box: OD writes in, what the station does out.
#include <gtest/gtest.h>

#include <vector>

#include "gateway/gateway.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

std::vector<uint16_t> g_rates;
std::vector<uint16_t> g_boot_ups;

bool log_frame(void*, const CanFrame& f) {
  if (f.id > 0x700 && f.id <= 0x77F && f.dlc == 1 && f.data[0] == 0)
    g_boot_ups.push_back(static_cast<uint16_t>(f.id));
  return true;
}
bool no_serial(void*, const uint8_t*, uint16_t) {
  return true;
}
void log_bitrate(void*, uint16_t kbit) {
  g_rates.push_back(kbit);
}
const CanControl kControl = {&log_bitrate, nullptr};

class EntryHandlers : public ::testing::Test {
 protected:
  void SetUp() override {
    g_rates.clear();
    g_boot_ups.clear();
    gw.start(0, 7);
    gw.process(0, 0);
  }
  SdoAbort write_u8(uint16_t index, uint8_t sub, uint8_t v) { return gw.od().write(index, sub, &v, 1); }
  SdoAbort write_u16(uint16_t index, uint8_t sub, uint16_t v) {
    uint8_t b[2];
    put_le16(b, v);
    return gw.od().write(index, sub, b, 2);
  }
  /// The check step of a Modbus request of several entries (apply false).
  SdoAbort check_u8(uint16_t index, uint8_t sub, uint8_t v) {
    return gw.od().write_row(gw.od().find(index, sub), &v, 1, false);
  }
  uint32_t get(uint16_t index, uint8_t sub) { return gw.od().get(gw.od().find(index, sub)); }
  void pass(uint32_t at_us) { gw.process(at_us, 0); }

  gateway::Gateway gw{gateway::GatewayPorts{
      CanSink{&log_frame, nullptr}, modbus::ByteSink{&no_serial, nullptr}, nullptr, 115200, &kControl}};
};

TEST_F(EntryHandlers, TheBitRateHandlerAdmitsTheControllersRatesOnly) {
  for (uint16_t kbit : {uint16_t{100}, uint16_t{200}, uint16_t{300}, uint16_t{800}, uint16_t{1001}}) {
    EXPECT_EQ(write_u16(0x2000, 2, kbit), kAbortInvalidValue) << kbit;
  }
  for (uint16_t kbit : {uint16_t{125}, uint16_t{250}, uint16_t{500}, uint16_t{1000}})
    EXPECT_EQ(write_u16(0x2000, 2, kbit), kSdoOk) << kbit;
  EXPECT_EQ(get(0x2000, 2), 1000u);
}

TEST_F(EntryHandlers, AWrittenIdAndRateCountFromTheNextResetCommunication) {
  ASSERT_EQ(write_u8(0x2000, 1, 9), kSdoOk);
  ASSERT_EQ(write_u16(0x2000, 2, 250), kSdoOk);
  pass(1000);
  EXPECT_EQ(gw.node_id(), 7) << "stored, not in force yet";
  g_rates.clear();
  g_boot_ups.clear();
  ASSERT_EQ(write_u8(0x2001, 0, 1), kSdoOk);  // restart request: reset communication
  EXPECT_EQ(get(0x2001, 0), 0u) << "a request reads back 0";
  pass(2000);
  EXPECT_EQ(gw.node_id(), 9);
  EXPECT_EQ(get(0x2000, 1), 9u);
  EXPECT_EQ(g_rates, std::vector<uint16_t>{250});
  EXPECT_EQ(g_boot_ups, std::vector<uint16_t>{0x709});
}

TEST_F(EntryHandlers, ResetNodeWithoutASavedSetGoesBackToThePowerOnId) {
  ASSERT_EQ(write_u8(0x2000, 1, 9), kSdoOk);
  g_boot_ups.clear();
  ASSERT_EQ(write_u8(0x2001, 0, 2), kSdoOk);  // reset node
  pass(1000);
  EXPECT_EQ(gw.node_id(), 7);
  EXPECT_EQ(get(0x2000, 1), 7u);
  EXPECT_EQ(g_boot_ups, std::vector<uint16_t>{0x707}) << "one boot-up, on the power-on id";
}

// The check step decides as the write would, and carries nothing out: no
// reset requested, no id taken (the value it leaves untracked is the
// caller's to put back: OdRegisterBank's undo log).
TEST_F(EntryHandlers, TheCheckStepCarriesNothingOut) {
  EXPECT_EQ(check_u8(0x2001, 0, 2), kSdoOk);
  EXPECT_EQ(check_u8(0x2000, 1, 9), kSdoOk);
  g_boot_ups.clear();
  pass(1000);
  pass(2000);
  EXPECT_EQ(g_boot_ups, std::vector<uint16_t>{}) << "no reset";
  ASSERT_EQ(write_u8(0x2001, 0, 1), kSdoOk);
  pass(3000);
  EXPECT_EQ(gw.node_id(), 7) << "the checked id was not taken";
}

// The maps' handler is the register bank's: a map entry naming an entry the
// table cannot carry is refused by SDO as by Modbus, and nothing is stored.
TEST_F(EntryHandlers, TheMapsHandlerIsTheRegisterBanks) {
  const uint32_t before = get(0x2400, 1);
  uint8_t b[4];
  put_le32(b, MB2CO_PDO_MAP_ENTRY(0x7777, 1, 8));  // no such entry
  EXPECT_NE(gw.od().write(0x2400, 1, b, 4), kSdoOk);
  EXPECT_EQ(get(0x2400, 1), before);
  put_le32(b, MB2CO_PDO_MAP_ENTRY(0x2000, 4, 8));
  EXPECT_EQ(gw.od().write(0x2400, 1, b, 4), kSdoOk);
  EXPECT_EQ(get(0x2400, 1), MB2CO_PDO_MAP_ENTRY(0x2000, 4, 8));
}

}  // namespace
}  // namespace test
}  // namespace mb2co
