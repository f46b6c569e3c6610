// FC 2B / MEI 0E read device identification: basic category, stream and
// individual access, conformity level 0x81.
#include <gtest/gtest.h>

#include <string>

#include "modbus/master_codec.h"
#include "support/slave_harness.h"

namespace mb2co {
namespace modbus {
namespace test {
namespace {

Bytes device_id(uint8_t code, uint8_t object) {
  Bytes adu(8);
  adu.resize(build_read_device_id(adu.data(), 8, kSlaveAddress, code, object));
  return adu;
}

Bytes exception(Exception code) {
  return with_crc({1, 0xAB, static_cast<uint8_t>(code)});
}

Bytes object_bytes(uint8_t id, const std::string& s) {
  Bytes b;
  b.push_back(id);
  b.push_back(static_cast<uint8_t>(s.size()));
  for (char c : s) b.push_back(static_cast<uint8_t>(c));
  return b;
}

Bytes response(uint8_t code, uint8_t more, uint8_t next, std::initializer_list<Bytes> objects) {
  Bytes b{1, 0x2B, 0x0E, code, 0x81, more, next, static_cast<uint8_t>(objects.size())};
  for (const Bytes& o : objects) b.insert(b.end(), o.begin(), o.end());
  return with_crc(b);
}

TEST(ModbusDeviceId, BasicStreamFromStartAndFromAnObject) {
  SlaveHarness h;
  EXPECT_EQ(
      h.transact(device_id(1, 0)),
      response(1, 0, 0, {object_bytes(0, "mb2co"), object_bytes(1, "MB2CO-GW"), object_bytes(2, "0.1.0")}));
  EXPECT_EQ(h.transact(device_id(1, 2)), response(1, 0, 0, {object_bytes(2, "0.1.0")}));
}

TEST(ModbusDeviceId, StreamFromUnknownObjectRestartsAtZero) {
  SlaveHarness h;
  const Bytes all = h.transact(device_id(1, 0));
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(h.transact(device_id(1, 3)), all);
  EXPECT_EQ(h.transact(device_id(1, 0x80)), all);
}

TEST(ModbusDeviceId, RegularAndExtendedAnsweredAtOurBasicLevel) {
  SlaveHarness h;
  for (uint8_t code : {uint8_t{2}, uint8_t{3}}) {
    EXPECT_EQ(h.transact(device_id(code, 0)),
              response(code, 0, 0,
                       {object_bytes(0, "mb2co"), object_bytes(1, "MB2CO-GW"), object_bytes(2, "0.1.0")}));
  }
}

TEST(ModbusDeviceId, IndividualAccess) {
  SlaveHarness h;
  EXPECT_EQ(h.transact(device_id(4, 0)), response(4, 0, 0, {object_bytes(0, "mb2co")}));
  EXPECT_EQ(h.transact(device_id(4, 1)), response(4, 0, 0, {object_bytes(1, "MB2CO-GW")}));
  EXPECT_EQ(h.transact(device_id(4, 2)), response(4, 0, 0, {object_bytes(2, "0.1.0")}));
  EXPECT_EQ(h.transact(device_id(4, 3)), exception(Exception::kIllegalDataAddress));
  EXPECT_EQ(h.transact(device_id(4, 0xFF)), exception(Exception::kIllegalDataAddress));
}

TEST(ModbusDeviceId, MalformedRequests) {
  SlaveHarness h;
  EXPECT_EQ(h.transact(device_id(0, 0)), exception(Exception::kIllegalDataValue));
  EXPECT_EQ(h.transact(device_id(5, 0)), exception(Exception::kIllegalDataValue));
  EXPECT_EQ(h.transact(with_crc({1, 0x2B, 0x0E, 0x01})), exception(Exception::kIllegalDataValue));
  EXPECT_EQ(h.transact(with_crc({1, 0x2B, 0x0E, 0x01, 0x00, 0x00})), exception(Exception::kIllegalDataValue));
  EXPECT_EQ(h.transact(with_crc({1, 0x2B})), exception(Exception::kIllegalDataValue));
  // Other MEI types (0x0D: CANopen general reference) are not supported.
  EXPECT_EQ(h.transact(with_crc({1, 0x2B, 0x0D, 0x01, 0x00})), exception(Exception::kIllegalFunction));
}

TEST(ModbusDeviceId, WithoutIdentityTheFunctionIsUnsupported) {
  SlaveHarness h;
  Bytes out;
  Slave bare(h.bank, nullptr, ByteSink{&keep_last, &out}, 1, h.timing);
  uint32_t t = 0;
  for (uint8_t b : device_id(1, 0)) bare.on_byte(b, t += h.timing.char_us);
  bare.process(t + h.timing.t35_us);
  EXPECT_EQ(out, exception(Exception::kIllegalFunction));
}

TEST(ModbusDeviceId, ObjectsThatDoNotFitContinueInTheNextTransaction) {
  SlaveHarness h;
  const std::string vendor(100, 'V'), product(100, 'P'), revision(100, 'R');
  h.identity = FixedIdentity(vendor, product, revision);
  // 7 header bytes + 2 × 102 fit in 253; the third object follows next time.
  const Bytes first = h.transact(device_id(1, 0));
  EXPECT_EQ(first, response(1, 0xFF, 2, {object_bytes(0, vendor), object_bytes(1, product)}));
  EXPECT_EQ(h.transact(device_id(1, 2)), response(1, 0, 0, {object_bytes(2, revision)}));
}

TEST(ModbusDeviceId, AnObjectLongerThanAResponseIsCut) {
  SlaveHarness h;
  h.identity = FixedIdentity(std::string(255, 'V'), "p", "r");
  const Bytes rsp = h.transact(device_id(4, 0));
  ASSERT_EQ(rsp.size(), 256u);  // the largest ADU
  EXPECT_EQ(rsp[9], 244) << "object length: 253 - 7 - 2";
  const Bytes stream = h.transact(device_id(1, 0));
  EXPECT_EQ(stream.size(), 256u);
  EXPECT_EQ(stream[5], 0xFF) << "more follows";
  EXPECT_EQ(stream[6], 1) << "next object";
}

}  // namespace
}  // namespace test
}  // namespace modbus
}  // namespace mb2co
