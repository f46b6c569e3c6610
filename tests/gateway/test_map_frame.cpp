// kMapFrameBytes, the Modbus frame buffer of the gateway on the Uno, holds
// every request the register maps can cover and its response, even with
// every map entry a 32-bit object (two registers each): the slave on that
// buffer answers them all, none is lost as an overrun.
#include <gtest/gtest.h>

#include <vector>

#include "gateway/gateway.h"
#include "modbus/master_codec.h"

namespace mb2co {
namespace {

using canopen::ObjectDictionary;

class MapFrame : public ::testing::Test {
 protected:
  void SetUp() override {
    od.restore_defaults(0x0000, 0xFFFF);
    // Every map entry 32 bits: the inputs show 2300h/1, the holding
    // registers 1016h/1 (readable and writable).
    fill_map(0x2401, gateway::kInputMapSize, MB2CO_PDO_MAP_ENTRY(0x2300, 1, 32));
    fill_map(0x2400, gateway::kHoldingMapSize, MB2CO_PDO_MAP_ENTRY(0x1016, 1, 32));
  }
  void fill_map(uint16_t index, uint8_t entries, uint32_t entry) {
    for (uint8_t sub = 0; sub <= entries; ++sub) {
      const uint16_t row = od.find(index, sub);
      const uint16_t no_row = ObjectDictionary::kNoRow;  // a copy: gtest takes references
      ASSERT_NE(row, no_row);
      od.set(row, sub == 0 ? entries : entry);  // local access: no map checks
      ASSERT_EQ(od.get(row), sub == 0 ? entries : entry);
    }
  }
  /// Sends `adu` after a quiet line and returns the response (empty: none).
  std::vector<uint8_t> transact(const uint8_t* adu, uint16_t length) {
    response.clear();
    now_us += timing.t35_us;
    for (uint16_t i = 0; i < length; ++i) {
      now_us += timing.char_us;
      slave.on_byte(adu[i], now_us);
    }
    now_us += timing.t35_us;
    slave.process(now_us);
    return response;
  }
  static bool keep(void* ctx, const uint8_t* data, uint16_t length) {
    static_cast<std::vector<uint8_t>*>(ctx)->assign(data, data + length);
    return true;
  }

  gateway::od::GatewayValues values{};
  ObjectDictionary od{gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values)};
  gateway::OdRegisterBank bank{od};
  gateway::OdDeviceIdentity identity{od};
  modbus::RtuTiming timing = modbus::rtu_timing(115200);
  std::vector<uint8_t> response;
  modbus::SlaveWithFrame<gateway::kMapFrameBytes> slave{bank, &identity, modbus::ByteSink{&keep, &response},
                                                        1, timing};
  uint32_t now_us = 1000000;
  uint8_t req[256] = {};
};

TEST_F(MapFrame, ReadOfTheWholeLongestMapFits) {
  const uint16_t registers = 2u * gateway::kInputMapSize;
  const uint16_t n =
      modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters, 0, registers);
  const std::vector<uint8_t> r = transact(req, n);
  ASSERT_EQ(r.size(), 3u + 2u * registers + 2u);
  EXPECT_EQ(r.size(), gateway::kMapFrameBytes);
  EXPECT_EQ(r[1], modbus::fc::kReadInputRegisters);
  EXPECT_EQ(slave.counters().char_overruns, 0u);
}

TEST_F(MapFrame, LongestWritesOfTheHoldingMapAreAnswered) {
  const uint16_t registers = 2u * gateway::kHoldingMapSize;
  std::vector<uint16_t> v(registers, 0);  // 1016h/1 = 0 everywhere: accepted
  uint16_t n = modbus::build_write_registers(req, sizeof req, 1, 0, registers, v.data());
  std::vector<uint8_t> r = transact(req, n);
  ASSERT_EQ(r.size(), 8u);
  EXPECT_EQ(r[1], modbus::fc::kWriteMultipleRegisters);
  n = modbus::build_read_write_registers(req, sizeof req, 1, 0, registers, 0, registers, v.data());
  ASSERT_LE(n, gateway::kMapFrameBytes);
  r = transact(req, n);
  ASSERT_EQ(r.size(), 3u + 2u * registers + 2u);
  EXPECT_EQ(r[1], modbus::fc::kReadWriteMultipleRegisters);
  EXPECT_EQ(slave.counters().char_overruns, 0u);
}

TEST_F(MapFrame, DeviceIdentificationIsNotCut) {
  const uint16_t n = modbus::build_read_device_id(req, sizeof req, 1, 1, 0);
  const std::vector<uint8_t> r = transact(req, n);
  ASSERT_GE(r.size(), 10u);
  EXPECT_EQ(r[5], 0u);  // no "more follows": all three objects in one response
  EXPECT_EQ(r[7], 3u);
}

}  // namespace
}  // namespace mb2co
