// Modbus registers as windows onto the gateway's OD (maps 2400h–2403h),
// exercised with real RTU frames through the gateway's slave.
#include <gtest/gtest.h>

#include <string>

#include "line_harness.h"

namespace mb2co {
namespace {

using modbus::Exception;
using modbus::ParseStatus;
using modbus::Response;
using test::Line;

// Holding register addresses of the default map (docs/register-map.md).
enum : uint16_t { kHrRun = 0, kHrLab = 1, kHrNodeId = 2, kHrBitrate = 3, kHrSyncPeriod = 9, kHrRestart = 13 };
// Input register addresses.
enum : uint16_t { kIrButtons = 0, kIrRun = 1, kIrStop2Count = 2, kIrEdgeHi = 12 };

struct Client {
  Line& line;
  uint8_t req[260];
  std::vector<uint8_t> raw;
  Response rsp;
  ParseStatus call(uint16_t len) {
    raw = line.modbus(0, req, len);
    if (raw.empty()) return ParseStatus::kTooShort;
    return modbus::parse_response(req, len, raw.data(), static_cast<uint16_t>(raw.size()), rsp);
  }
  ParseStatus read(uint8_t fc, uint16_t start, uint16_t n) {
    return call(modbus::build_read_request(req, sizeof req, 1, fc, start, n));
  }
  ParseStatus write1(uint16_t reg, uint16_t v) {
    return call(modbus::build_write_single_register(req, sizeof req, 1, reg, v));
  }
  ParseStatus write_n(uint16_t start, std::vector<uint16_t> v) {
    return call(
        modbus::build_write_registers(req, sizeof req, 1, start, static_cast<uint16_t>(v.size()), v.data()));
  }
};

class RegisterMap : public ::testing::Test {
 protected:
  Line line{1};
  Client c{line, {}, {}, {}};
  void SetUp() override { line.run_ms(50); }
};

TEST_F(RegisterMap, InputRegistersShowTheOdEntriesTheyMap) {
  line.station(0).buttons = gateway::kStop2;
  line.run_ms(40);
  ASSERT_EQ(c.read(modbus::fc::kReadInputRegisters, 0, 16), ParseStatus::kOk);
  EXPECT_EQ(c.rsp.reg(kIrButtons), gateway::kStop2);
  EXPECT_EQ(c.rsp.reg(kIrStop2Count), 1u);
  // A 32-bit entry spans two registers, high word first.
  const uint32_t edge = line.od_get(0, 0x2300, 1);
  ASSERT_NE(edge, 0u);
  EXPECT_EQ((static_cast<uint32_t>(c.rsp.reg(kIrEdgeHi)) << 16) | c.rsp.reg(kIrEdgeHi + 1), edge);
}

TEST_F(RegisterMap, HoldingRegisterWriteLandsInTheOd) {
  ASSERT_EQ(c.write1(kHrRun, 1), ParseStatus::kOk);
  EXPECT_EQ(line.od_get(0, 0x2100, 1), 1u);
  line.run_ms(5);
  ASSERT_EQ(c.read(modbus::fc::kReadInputRegisters, kIrRun, 1), ParseStatus::kOk);
  EXPECT_EQ(c.rsp.reg(0), 1u);  // the RUN state followed the command
}

TEST_F(RegisterMap, A32BitValueIsWrittenWholeByOneRequestOrNotAtAll) {
  ASSERT_EQ(c.write_n(kHrSyncPeriod, {0x0001, 0x86A0}), ParseStatus::kOk);
  EXPECT_EQ(line.od_get(0, 0x1006, 0), 100000u);
  // Half of it alone is not an address one can write: exception 02.
  ASSERT_EQ(c.write1(kHrSyncPeriod + 1, 5), ParseStatus::kException);
  EXPECT_EQ(c.rsp.exception, Exception::kIllegalDataAddress);
  EXPECT_EQ(line.od_get(0, 0x1006, 0), 100000u);
}

TEST_F(RegisterMap, ARefusedValueLeavesEveryRegisterOfTheRequestUnchanged) {
  // RUN command 1, lab LED 1, node id 0 (below 1): the OD refuses the last.
  ASSERT_EQ(c.write_n(kHrRun, {1, 1, 0}), ParseStatus::kException);
  EXPECT_EQ(c.rsp.exception, Exception::kServerDeviceFailure);
  EXPECT_EQ(line.od_get(0, 0x2100, 1), 0u);
  EXPECT_EQ(line.od_get(0, 0x6200, 1), 0u);
  EXPECT_EQ(line.od_get(0, 0x2000, 1), 1u);
  ASSERT_EQ(c.write1(kHrBitrate, 300), ParseStatus::kException);  // not a CANopen bit rate
  EXPECT_EQ(c.rsp.exception, Exception::kServerDeviceFailure);
  ASSERT_EQ(c.write1(kHrBitrate, 250), ParseStatus::kOk);
  EXPECT_EQ(line.od_get(0, 0x2000, 2), 250u);
}

TEST_F(RegisterMap, ReadOnlyEntriesRefuseWritesWithException02) {
  // Remap holding register 0 onto the RUN *state* (read-only) by SDO.
  uint8_t entry[4];
  canopen::put_le32(entry, MB2CO_PDO_MAP_ENTRY(0x2100, 2, 8));
  ASSERT_EQ(line.gw(0).od().write(0x2400, 1, entry, 4), canopen::kSdoOk);
  ASSERT_EQ(c.write1(0, 1), ParseStatus::kException);
  EXPECT_EQ(c.rsp.exception, Exception::kIllegalDataAddress);
  ASSERT_EQ(c.read(modbus::fc::kReadHoldingRegisters, 0, 1), ParseStatus::kOk);  // still readable
  // Beyond the map: 02 as well.
  ASSERT_EQ(c.read(modbus::fc::kReadHoldingRegisters, 100, 1), ParseStatus::kException);
  EXPECT_EQ(c.rsp.exception, Exception::kIllegalDataAddress);
}

TEST_F(RegisterMap, MapEntriesAreValidatedWhenWrittenBySdo) {
  uint8_t entry[4];
  canopen::put_le32(entry, MB2CO_PDO_MAP_ENTRY(0x1008, 0, 8));  // a string
  EXPECT_EQ(line.gw(0).od().write(0x2400, 1, entry, 4), canopen::kAbortInvalidValue);
  canopen::put_le32(entry, MB2CO_PDO_MAP_ENTRY(0x2100, 1, 16));  // 16 bits of an 8-bit entry
  EXPECT_EQ(line.gw(0).od().write(0x2400, 1, entry, 4), canopen::kAbortInvalidValue);
  canopen::put_le32(entry, MB2CO_PDO_MAP_ENTRY(0x5FFF, 0, 8));
  EXPECT_EQ(line.gw(0).od().write(0x2400, 1, entry, 4), canopen::kAbortNoObject);
  const uint8_t too_many = gateway::kHoldingMapSize + 1;
  EXPECT_EQ(line.gw(0).od().write(0x2400, 0, &too_many, 1), canopen::kAbortValueTooHigh);
}

TEST_F(RegisterMap, CoilsAndDiscreteInputs) {
  ASSERT_EQ(c.call(modbus::build_write_single_coil(c.req, sizeof c.req, 1, 1, true)), ParseStatus::kOk);
  EXPECT_EQ(line.od_get(0, 0x6200, 1), 1u);
  line.run_ms(2);
  EXPECT_TRUE(line.station(0).leds & gateway::kLedLab);
  EXPECT_NE(line.od_get(0, 0x2300, 2), 0u);  // LED change timestamp
  line.station(0).buttons = gateway::kStart;
  line.run_ms(40);
  ASSERT_EQ(c.read(modbus::fc::kReadDiscreteInputs, 0, 7), ParseStatus::kOk);
  EXPECT_TRUE(c.rsp.bit(0));   // START
  EXPECT_FALSE(c.rsp.bit(1));  // STOP
}

TEST_F(RegisterMap, ReadWriteInOneTransaction) {
  const uint16_t v = 1;
  ASSERT_EQ(c.call(modbus::build_read_write_registers(c.req, sizeof c.req, 1, 0, 2, kHrLab, 1, &v)),
            ParseStatus::kOk);
  EXPECT_EQ(c.rsp.reg(1), 1u);  // the write happens before the read
}

TEST_F(RegisterMap, DeviceIdentificationComesFromTheOd) {
  ASSERT_EQ(c.call(modbus::build_read_device_id(c.req, sizeof c.req, 1, 1, 0)), ParseStatus::kOk);
  std::string product;
  for (uint8_t k = 0; k < c.rsp.object_count; ++k) {
    uint8_t id = 0, len = 0;
    const uint8_t* value = nullptr;
    ASSERT_TRUE(modbus::device_id_object(c.rsp, k, id, value, len));
    if (id == 1) product.assign(reinterpret_cast<const char*>(value), len);
  }
  EXPECT_EQ(product, "mb2co gateway");
}

TEST_F(RegisterMap, RestartRequestResetsCommunicationAfterTheResponse) {
  line.log.clear();
  ASSERT_EQ(c.write1(kHrRestart, 1), ParseStatus::kOk);
  line.run_ms(5);
  bool bootup = false;
  for (const auto& s : line.log) bootup = bootup || (s.frame.id == 0x701 && s.frame.data[0] == 0);
  EXPECT_TRUE(bootup);
}

}  // namespace
}  // namespace mb2co
