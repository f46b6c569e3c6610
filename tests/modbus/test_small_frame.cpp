// A slave on a frame buffer smaller than the protocol's 256 bytes (the Uno's
// gateway: shared/gateway/gateway.h kModbusFrameBytes). Requests and
// responses that fit behave exactly as with the full buffer; a longer request
// is lost as an overrun (CPT8, no answer); a covered read whose response
// would not fit is exception 04, decided before anything is written.
#include <gtest/gtest.h>

#include <vector>

#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

constexpr uint16_t kSmall = 32;  // responses up to 13 registers, requests up to 32 bytes

/// Like SlaveHarness (same bank layout and timing), on SlaveWithFrame<kSmall>.
class SmallSlave {
 public:
  SmallSlave()
      : bank(kCoilCount, kDiscreteInputCount, kInputRegisterCount, kHoldingRegisterCount),
        identity(test_identity()),
        timing(rtu_timing(SlaveHarness::kBaud)),
        slave(bank, &identity, ByteSink{&keep_last, &response}, kSlaveAddress, timing) {
    apply_test_layout(bank);
  }

  /// Sends `adu` after a quiet line, lets the frame end; the response or {}.
  Bytes transact(const Bytes& adu) {
    response.clear();
    now_us += timing.t35_us;
    for (uint8_t b : adu) {
      now_us += timing.char_us;
      slave.on_byte(b, now_us);
    }
    now_us += timing.t35_us;
    slave.process(now_us);
    return response;
  }

  MemoryBank bank;
  FixedIdentity identity;
  RtuTiming timing;
  SlaveWithFrame<kSmall> slave;
  Bytes response;
  uint32_t now_us = 1000000u;
};

Bytes exception(uint8_t function, Exception e) {
  return with_crc(
      {kSlaveAddress, static_cast<uint8_t>(function | fc::kExceptionFlag), static_cast<uint8_t>(e)});
}

Bytes write_registers(uint16_t start, uint16_t quantity, uint16_t value) {
  std::vector<uint16_t> values(quantity, value);
  Bytes adu(256);
  adu.resize(build_write_registers(adu.data(), 256, kSlaveAddress, start, quantity, values.data()));
  return adu;
}

TEST(ModbusSmallFrame, RequestsThatFitAnswerLikeTheFullSlave) {
  SlaveHarness full;
  SmallSlave small;
  std::vector<Bytes> requests;
  for (uint16_t q = 1; q <= 13; ++q) requests.push_back(read_holding(kReadOnlyStart, q));
  for (uint16_t q = 1; q <= 11; ++q) requests.push_back(write_registers(20, q, q));
  requests.push_back(write_register(kLimitedStart, kLimitMax + 1));  // 04 from the bank
  requests.push_back(write_register(kReadOnlyStart, 1));             // 02
  requests.push_back(read_holding(0, 126));                          // 03
  requests.push_back(read_holding(250, 100));                        // 02: not covered
  Bytes coils(8);
  coils.resize(build_read_request(coils.data(), 8, kSlaveAddress, fc::kReadCoils, 0, 200));
  requests.push_back(coils);  // 25 data bytes: fits
  for (const Bytes& r : requests) {
    const Bytes expected = full.transact(r);
    ASSERT_FALSE(expected.empty());
    EXPECT_EQ(small.transact(r), expected) << "request of " << r.size() << " bytes, FC " << int(r[1]);
  }
  EXPECT_EQ(small.slave.counters().char_overruns, 0u);
  EXPECT_EQ(small.bank.holding_registers, full.bank.holding_registers);
}

TEST(ModbusSmallFrame, LongerRequestIsAnOverrunAndChangesNothing) {
  SmallSlave small;
  const Bytes adu = write_registers(20, 12, 7);  // 9 + 24 = 33 bytes > 32
  ASSERT_EQ(adu.size(), kSmall + 1u);
  EXPECT_TRUE(small.transact(adu).empty());
  EXPECT_EQ(small.slave.counters().char_overruns, 1u);
  EXPECT_EQ(small.slave.counters().bus_comm_errors, 0u);
  EXPECT_EQ(small.bank.holding_registers[20], 0);
  // The next request is received normally.
  EXPECT_FALSE(small.transact(read_holding(0, 1)).empty());
  EXPECT_EQ(small.slave.counters().char_overruns, 1u);
}

TEST(ModbusSmallFrame, CoveredReadThatWouldNotFitIsException04) {
  SmallSlave small;
  EXPECT_EQ(small.transact(read_holding(0, 14)),
            exception(fc::kReadHoldingRegisters, Exception::kServerDeviceFailure));
  // Quantity (03) and address (02) checks still come first.
  EXPECT_EQ(small.transact(read_holding(0, 126)),
            exception(fc::kReadHoldingRegisters, Exception::kIllegalDataValue));
  EXPECT_EQ(small.transact(read_holding(250, 14)),
            exception(fc::kReadHoldingRegisters, Exception::kIllegalDataAddress));
  Bytes bits(8);
  bits.resize(build_read_request(bits.data(), 8, kSlaveAddress, fc::kReadDiscreteInputs, 0, 2000));
  EXPECT_EQ(small.transact(bits), exception(fc::kReadDiscreteInputs, Exception::kServerDeviceFailure));
}

TEST(ModbusSmallFrame, ReadWriteThatWouldNotFitWritesNothing) {
  SmallSlave small;
  const uint16_t values[2] = {5, 6};
  Bytes adu(32);
  adu.resize(build_read_write_registers(adu.data(), 32, kSlaveAddress, 0, 14, 30, 2, values));
  ASSERT_LE(adu.size(), kSmall);
  EXPECT_EQ(small.transact(adu), exception(fc::kReadWriteMultipleRegisters, Exception::kServerDeviceFailure));
  EXPECT_EQ(small.bank.holding_registers[30], 0);
  adu.resize(32);
  adu.resize(build_read_write_registers(adu.data(), 32, kSlaveAddress, 0, 13, 30, 2, values));
  const Bytes r = small.transact(adu);
  ASSERT_EQ(r.size(), 3u + 26u + 2u);
  EXPECT_EQ(small.bank.holding_registers[30], 5);
}

TEST(ModbusSmallFrame, DeviceIdentificationIsCutToTheBuffer) {
  SmallSlave small;
  small.identity = FixedIdentity("a-rather-long-vendor-name", "MB2CO-GW", "0.1.0");
  Bytes adu(8);
  adu.resize(build_read_device_id(adu.data(), 8, kSlaveAddress, 1, 0));
  const Bytes r = small.transact(adu);
  ASSERT_EQ(r.size(), kSmall);
  EXPECT_EQ(r[1], fc::kEncapsulatedInterface);
  // address, 2B, 0E, code, conformity, more follows, next id, count, objects
  EXPECT_EQ(r[5], 0xFFu);  // more follow,
  EXPECT_EQ(r[6], 1u);     // from object 1;
  EXPECT_EQ(r[7], 1u);     // one object in this transaction:
  EXPECT_EQ(r[8], 0u);     // object 0, cut to the room left (32 - 3 - 9)
  EXPECT_EQ(r[9], kSmall - 3u - 9u);
  EXPECT_EQ(Bytes(r.begin() + 10, r.end() - 2),
            Bytes(small.identity.object(0).begin(), small.identity.object(0).begin() + r[9]));
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
