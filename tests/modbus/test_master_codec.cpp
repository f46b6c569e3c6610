// The master-side codec against the slave: every function code round-trips,
// exceptions are decoded, broken responses are rejected.
#include <gtest/gtest.h>

#include <string>

#include "modbus/master_codec.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

class ModbusMasterCodec : public ::testing::Test {
 protected:
  SlaveHarness h;
  uint8_t req[256];
  uint16_t req_len = 0;
  Bytes rsp;
  Response r;

  ParseStatus round_trip(uint16_t length) {
    EXPECT_GT(length, 0u);
    req_len = length;
    rsp = h.transact(Bytes(req, req + length));
    return parse_response(req, req_len, rsp.data(), static_cast<uint16_t>(rsp.size()), r);
  }
};

TEST_F(ModbusMasterCodec, ReadsRoundTrip) {
  h.bank.coils[1] = h.bank.coils[8] = true;
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x01, 0, 9)), ParseStatus::kOk);
  EXPECT_EQ(r.data_length, 2u);
  EXPECT_FALSE(r.bit(0));
  EXPECT_TRUE(r.bit(1));
  EXPECT_TRUE(r.bit(8));
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x02, 3, 2000)), ParseStatus::kOk);
  EXPECT_TRUE(r.bit(0));   // input 3
  EXPECT_FALSE(r.bit(1));  // input 4
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x04, 5, 125)), ParseStatus::kOk);
  EXPECT_EQ(r.reg(0), 0x1005);
  EXPECT_EQ(r.reg(124), 0x1005 + 124);
  h.bank.holding_registers[9] = 77;
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x03, 9, 1)), ParseStatus::kOk);
  EXPECT_EQ(r.reg(0), 77);
  EXPECT_EQ(build_read_request(req, 256, 1, 0x05, 0, 1), 0u) << "not a read";
}

TEST_F(ModbusMasterCodec, WritesRoundTrip) {
  ASSERT_EQ(round_trip(build_write_single_coil(req, 256, 1, 4, true)), ParseStatus::kOk);
  EXPECT_TRUE(h.bank.coils[4]);
  ASSERT_EQ(round_trip(build_write_single_register(req, 256, 1, 4, 0x4444)), ParseStatus::kOk);
  EXPECT_EQ(h.bank.holding_registers[4], 0x4444);
  const uint8_t packed[2] = {0xFF, 0x01};
  ASSERT_EQ(round_trip(build_write_coils(req, 256, 1, 100, 9, packed)), ParseStatus::kOk);
  EXPECT_TRUE(h.bank.coils[108]);
  const uint16_t values[3] = {1, 2, 3};
  ASSERT_EQ(round_trip(build_write_registers(req, 256, 1, 20, 3, values)), ParseStatus::kOk);
  EXPECT_EQ(h.bank.holding_registers[22], 3);
  ASSERT_EQ(round_trip(build_read_write_registers(req, 256, 1, 19, 4, 23, 1, values)), ParseStatus::kOk);
  EXPECT_EQ(r.reg(0), 0);
  EXPECT_EQ(r.reg(3), 3);
  EXPECT_EQ(h.bank.holding_registers[23], 1);
}

TEST_F(ModbusMasterCodec, DiagnosticsAndDeviceIdRoundTrip) {
  const uint8_t data[5] = {9, 8, 7, 6, 5};
  ASSERT_EQ(round_trip(build_diagnostics(req, 256, 1, diag::kReturnQueryData, data, 5)), ParseStatus::kOk);
  EXPECT_EQ(r.data_length, 5u);
  ASSERT_EQ(round_trip(build_diagnostics(req, 256, 1, diag::kServerMessageCount, 0)), ParseStatus::kOk);
  EXPECT_EQ(r.diag_value(), 2u);
  ASSERT_EQ(round_trip(build_read_device_id(req, 256, 1, 1, 0)), ParseStatus::kOk);
  EXPECT_EQ(r.conformity, 0x81);
  ASSERT_EQ(r.object_count, 3u);
  for (uint8_t i = 0; i < 3; ++i) {
    uint8_t id = 0, length = 0;
    const uint8_t* value = nullptr;
    ASSERT_TRUE(device_id_object(r, i, id, value, length));
    EXPECT_EQ(id, i);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(value), length), h.identity.object(i));
  }
  uint8_t id, length;
  const uint8_t* value;
  EXPECT_FALSE(device_id_object(r, 3, id, value, length));
}

TEST_F(ModbusMasterCodec, ExceptionsDecoded) {
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x03, 0, 126)), ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalDataValue);
  ASSERT_EQ(round_trip(build_write_single_register(req, 256, 1, kReadOnlyStart, 1)), ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalDataAddress);
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x04, kFailingInputRegister, 1)),
            ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kServerDeviceFailure);
  ASSERT_EQ(round_trip(build_diagnostics(req, 256, 1, 0x03, 0)), ParseStatus::kException);
  EXPECT_EQ(r.exception, Exception::kIllegalFunction);
}

TEST_F(ModbusMasterCodec, BroadcastGetsNoResponse) {
  req_len = build_write_single_register(req, 256, 0, 1, 1);
  EXPECT_TRUE(h.transact(Bytes(req, req + req_len)).empty());
  EXPECT_EQ(h.bank.holding_registers[1], 1);
}

TEST_F(ModbusMasterCodec, BrokenResponsesRejected) {
  ASSERT_EQ(round_trip(build_read_request(req, 256, 1, 0x03, 0, 2)), ParseStatus::kOk);
  const Bytes good = rsp;
  auto parse = [&](const Bytes& b) {
    return parse_response(req, req_len, b.data(), static_cast<uint16_t>(b.size()), r);
  };
  Bytes b = good;
  b[3] ^= 1;
  EXPECT_EQ(parse(b), ParseStatus::kBadCrc);
  EXPECT_EQ(parse(Bytes(good.begin(), good.begin() + 4)), ParseStatus::kTooShort);
  EXPECT_EQ(parse(with_crc({2, 0x03, 4, 0, 0, 0, 0})), ParseStatus::kWrongAddress);
  EXPECT_EQ(parse(with_crc({1, 0x04, 4, 0, 0, 0, 0})), ParseStatus::kWrongFunction);
  EXPECT_EQ(parse(with_crc({1, 0x03, 2, 0, 0})), ParseStatus::kBadLength);
  EXPECT_EQ(parse(with_crc({1, 0x03, 4, 0, 0, 0})), ParseStatus::kBadLength);
  EXPECT_EQ(parse(with_crc({1, 0x83, 2, 0})), ParseStatus::kBadLength);

  req_len = build_write_single_register(req, 256, 1, 4, 5);
  EXPECT_EQ(parse(with_crc({1, 0x06, 0, 4, 0, 6})), ParseStatus::kMismatch);
  req_len = build_diagnostics(req, 256, 1, diag::kClearCounters, 0);
  EXPECT_EQ(parse(with_crc({1, 0x08, 0, 0x0A, 0, 1})), ParseStatus::kMismatch);
  EXPECT_EQ(parse(with_crc({1, 0x08, 0, 0x0B, 0, 0})), ParseStatus::kMismatch);
  req_len = build_read_device_id(req, 256, 1, 1, 0);
  EXPECT_EQ(parse(with_crc({1, 0x2B, 0x0E, 1, 0x81, 0, 0, 1, 0, 5, 'a'})), ParseStatus::kBadLength);
  EXPECT_EQ(parse(with_crc({1, 0x2B, 0x0E, 1, 0x81, 0, 0, 1, 0, 1, 'a'})), ParseStatus::kOk);
}

TEST_F(ModbusMasterCodec, BuildersRespectCapacity) {
  EXPECT_EQ(build_read_request(req, 7, 1, 0x03, 0, 1), 0u);
  EXPECT_EQ(build_read_request(req, 8, 1, 0x03, 0, 1), 8u);
  const uint16_t values[124] = {};
  EXPECT_EQ(build_write_registers(req, 256, 1, 0, 123, values), 255u);
  EXPECT_EQ(build_write_registers(req, 256, 1, 0, 124, values), 0u) << "longer than an ADU";
  const uint8_t packed[256] = {};
  EXPECT_EQ(build_write_coils(req, 256, 1, 0, 1968, packed), 255u);
  EXPECT_EQ(build_write_coils(req, 256, 1, 0, 2041, packed), 0u);
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
