// The master's EMCY consumer (canopen/master/emcy_consumer.h, emcy_names.h):
// hand-written frames decoded field by field, CiA 301's classes and register
// bits named, and the EMCYs a real node of the node core produces (an error
// and its reset, a SYNC length error, a PDO length error) decoded on a
// virtual bus.
#include <gtest/gtest.h>

#include <string>

#include "canopen/emcy_producer.h"
#include "canopen/frame_out.h"
#include "canopen/master/emcy_consumer.h"
#include "canopen/master/emcy_names.h"
#include "canopen/master/nmt_master.h"
#include "test_master_bus.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;
using Strings = std::vector<std::string>;

/// The listener's view: "3 8110 11 01 02 03 04 05 @t".
struct EmcyLog {
  EmcyListener listener() { return EmcyListener{&EmcyLog::on, this}; }
  static void on(void* ctx, uint8_t id, const EmcyMessage& m, uint32_t now_us) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%u %04X %02X %02X %02X %02X %02X %02X @%u", id, m.code, m.error_register,
                  m.manufacturer[0], m.manufacturer[1], m.manufacturer[2], m.manufacturer[3],
                  m.manufacturer[4], static_cast<unsigned>(now_us));
    static_cast<EmcyLog*>(ctx)->seen.push_back(buf);
  }
  Strings seen;
};

TEST(MasterEmcy, DecodesAHandWrittenFrameFieldByField) {
  EmcyConsumer<4> emcy;
  EmcyLog log;
  emcy.set_listener(log.listener());
  EXPECT_TRUE(emcy.on_frame(F(0x083, {0x10, 0x81, 0x11, 0x01, 0x02, 0x03, 0x04, 0x05}), 1234));
  EXPECT_EQ(log.seen, Strings({"3 8110 11 01 02 03 04 05 @1234"}));
  const EmcyRecord* r = emcy.record(3);
  ASSERT_NE(r, nullptr);
  EXPECT_EQ(r->last.code, 0x8110u);
  EXPECT_EQ(r->last.error_register, kErrGeneric | kErrCommunication);
  EXPECT_EQ(r->last_us, 1234u);
  EXPECT_EQ(r->count, 1u);
  EXPECT_EQ(emcy_class(r->last.code), kEmcyClassCommunication);
  EXPECT_STREQ(emcy_code_name(r->last.code), "CAN overrun");
  EXPECT_STREQ(emcy_class_name(emcy_class(r->last.code)), "communication");
  EXPECT_EQ(emcy.record(4), nullptr);
  EXPECT_EQ(emcy.count(4), 0u);
}

TEST(MasterEmcy, OtherFramesAreNotEmcys) {
  EmcyConsumer<4> emcy;
  EXPECT_FALSE(emcy.on_frame(F(0x080, {}), 0)) << "SYNC";
  EXPECT_FALSE(emcy.on_frame(F(0x100, {0, 0, 0, 0, 0, 0, 0, 0}), 0));
  EXPECT_FALSE(emcy.on_frame(F(0x183, {0, 0, 0, 0, 0, 0, 0, 0}), 0));
  EXPECT_EQ(emcy.malformed(), 0u);
  EXPECT_FALSE(emcy.on_frame(F(0x083, {0x10, 0x81, 0x11}), 0)) << "EMCYs are 8 bytes";
  EXPECT_FALSE(emcy.on_frame(Rtr(0x083, 8), 0));
  EXPECT_EQ(emcy.malformed(), 2u);
  EXPECT_EQ(emcy.record(3), nullptr);
}

TEST(MasterEmcy, ClassesOfCiA301TableAndTheirNames) {
  const struct {
    uint16_t code;
    EmcyClass cls;
    const char* name;
  } cases[] = {
      {0x0000, kEmcyClassErrorReset, "error reset"},
      {0x1000, kEmcyClassGeneric, "generic"},
      {0x2310, kEmcyClassCurrent, "current"},
      {0x3210, kEmcyClassVoltage, "voltage"},
      {0x4210, kEmcyClassTemperature, "temperature"},
      {0x5000, kEmcyClassDeviceHardware, "device hardware"},
      {0x6100, kEmcyClassDeviceSoftware, "device software"},
      {0x7000, kEmcyClassAdditionalModules, "additional modules"},
      {0x8000, kEmcyClassMonitoring, "monitoring"},
      {0x8110, kEmcyClassCommunication, "communication"},
      {0x8130, kEmcyClassCommunication, "communication"},
      {0x8210, kEmcyClassProtocol, "protocol error"},
      {0x9000, kEmcyClassExternal, "external"},
      {0xF000, kEmcyClassAdditionalFunctions, "additional functions"},
      {0xFF42, kEmcyClassDeviceSpecific, "device specific"},
      {0x0001, kEmcyClassUnknown, "unknown"},
      {0x1100, kEmcyClassUnknown, "unknown"},
      {0xA000, kEmcyClassUnknown, "unknown"},
  };
  for (const auto& c : cases) {
    EXPECT_EQ(emcy_class(c.code), c.cls) << std::hex << c.code;
    EXPECT_STREQ(emcy_class_name(emcy_class(c.code)), c.name) << std::hex << c.code;
  }
  // The communication and protocol codes are named to the digit; others by class.
  EXPECT_STREQ(emcy_code_name(0x8120), "CAN in error passive mode");
  EXPECT_STREQ(emcy_code_name(0x8130), "life guard or heartbeat error");
  EXPECT_STREQ(emcy_code_name(0x8140), "recovered from bus-off");
  EXPECT_STREQ(emcy_code_name(0x8210), "PDO length error");
  EXPECT_STREQ(emcy_code_name(0x8220), "PDO length exceeded");
  EXPECT_STREQ(emcy_code_name(0x8240), "unexpected SYNC data length");
  EXPECT_STREQ(emcy_code_name(0x8250), "RPDO timeout");
  EXPECT_STREQ(emcy_code_name(0x8111), "communication");
  EXPECT_STREQ(emcy_code_name(0x0000), "error reset");
  EXPECT_STREQ(emcy_code_name(0x4210), "temperature");
}

TEST(MasterEmcy, ErrorRegisterBitNames) {
  EXPECT_STREQ(error_register_bit_name(kErrGeneric), "generic");
  EXPECT_STREQ(error_register_bit_name(kErrCurrent), "current");
  EXPECT_STREQ(error_register_bit_name(kErrVoltage), "voltage");
  EXPECT_STREQ(error_register_bit_name(kErrTemperature), "temperature");
  EXPECT_STREQ(error_register_bit_name(kErrCommunication), "communication");
  EXPECT_STREQ(error_register_bit_name(kErrDeviceProfile), "device profile specific");
  EXPECT_STREQ(error_register_bit_name(kErrManufacturer), "manufacturer specific");
  EXPECT_EQ(error_register_bit_name(0x40), nullptr) << "reserved";
  EXPECT_EQ(error_register_bit_name(0x00), nullptr);
  EXPECT_EQ(error_register_bit_name(0x03), nullptr) << "one bit at a time";
}

TEST(MasterEmcy, KeepsTheLastPerNodeAndCountsThoseItHasNoRoomFor) {
  EmcyConsumer<2> emcy;
  EmcyLog log;
  emcy.set_listener(log.listener());
  emcy.on_frame(F(0x083, {0x00, 0x10, 0x01, 0, 0, 0, 0, 0}), 10);
  emcy.on_frame(F(0x085, {0x00, 0x50, 0x01, 0, 0, 0, 0, 0}), 20);
  emcy.on_frame(F(0x083, {0x00, 0x00, 0x00, 0, 0, 0, 0, 0}), 30);
  EXPECT_TRUE(emcy.on_frame(F(0x0FF, {0x00, 0x90, 0x01, 0, 0, 0, 0, 0}), 40))
      << "node 127: decoded all the same";
  EXPECT_EQ(log.seen.size(), 4u);
  EXPECT_EQ(emcy.count(3), 2u);
  EXPECT_EQ(emcy.record(3)->last.code, 0x0000u);
  EXPECT_EQ(emcy.record(3)->last_us, 30u);
  EXPECT_EQ(emcy.count(5), 1u);
  EXPECT_EQ(emcy.record(127), nullptr);
  EXPECT_EQ(emcy.unrecorded(), 1u);
  emcy.clear();
  EXPECT_EQ(emcy.record(3), nullptr);
}

TEST(MasterEmcy, DecodesTheEmcysOfARealNode) {
  MasterBus bus;
  EmcyConsumer<8> emcy;
  EmcyLog log;
  emcy.set_listener(log.listener());
  bus.master_rx = [&](const CanFrame& f, uint32_t t) { emcy.on_frame(f, t); };
  MasterBus::Station& node = bus.add_node(3);

  // An error the application raises, and its end ("error reset").
  const uint8_t info[5] = {0xDE, 0xAD, 0xBE, 0xEF, 0x01};
  node.io.node().emcy().raise(0x4210, kErrTemperature, info);
  bus.step(100);
  node.io.node().emcy().clear(0x4210);
  bus.step(100);
  ASSERT_EQ(log.seen, Strings({"3 4210 09 DE AD BE EF 01 @100", "3 0000 00 00 00 00 00 00 @200"}));
  EXPECT_EQ(emcy.count(3), 2u);
  EXPECT_EQ(emcy_class(emcy.record(3)->last.code), kEmcyClassErrorReset);

  // The node's own communication errors: a SYNC with a byte it does not expect...
  log.seen.clear();
  ASSERT_TRUE(send_frame(bus.master_sink(), 0x080, 1, info));
  bus.run(200);
  ASSERT_EQ(log.seen.size(), 1u);
  const EmcyMessage sync_error = emcy.record(3)->last;
  EXPECT_EQ(sync_error.code, 0x8240u);
  EXPECT_TRUE(sync_error.error_register & kErrCommunication);
  EXPECT_STREQ(emcy_code_name(sync_error.code), "unexpected SYNC data length");
  EXPECT_EQ(emcy_class(sync_error.code), kEmcyClassProtocol);

  // ...and, operational, an RPDO1 shorter than its mapping (2 bytes).
  NmtMaster(bus.master_sink()).start(3);
  bus.deliver();
  log.seen.clear();
  ASSERT_TRUE(send_frame(bus.master_sink(), 0x203, 1, info));
  bus.run(200);
  ASSERT_EQ(log.seen.size(), 1u);
  EXPECT_EQ(emcy.record(3)->last.code, 0x8210u);
  EXPECT_STREQ(emcy_code_name(emcy.record(3)->last.code), "PDO length error");
  EXPECT_EQ(emcy.count(3), 4u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
