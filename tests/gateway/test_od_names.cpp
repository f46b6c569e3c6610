// Named OD entries (od_define.h's identifier column) and the rule that keeps
// the TPDOs honest: an entry a PDO may map is a PdoMapped member of the value
// block, which only ObjectDictionary::put() stores into, and put() tells the
// OD of every change. White box (the generated types), then black box (the
// frames on the bus).
#include <gtest/gtest.h>

#include <type_traits>

#include "gateway/gateway_od.h"
#include "line_harness.h"

namespace mb2co {
namespace {

using namespace canopen;  // the list's flags (kAttrPdo, ...) read unqualified
using gateway::od::GatewayValues;
namespace e = gateway::od::GatewayEntry;

// Every RAM row of the gateway OD at compile time: PDO-mappable exactly when
// a plain assignment of its type does not compile.
#define MB2CO_TEST_ASSIGNABLE_CONST(t, flags, id)
#define MB2CO_TEST_ASSIGNABLE_RO(t, flags, id)                                                 \
  static_assert(std::is_assignable<decltype(GatewayValues::id)&, MB2CO_OD_CTYPE_##t>::value == \
                    (((flags)&kAttrPdo) == 0),                                                 \
                #id ": PDO-mappable entries are stored through ObjectDictionary::put() only");
#define MB2CO_TEST_ASSIGNABLE_WO MB2CO_TEST_ASSIGNABLE_RO
#define MB2CO_TEST_ASSIGNABLE_RW MB2CO_TEST_ASSIGNABLE_RO
#define MB2CO_TEST_N_ASSIGNABLE(index, sub, id, t, access, flags, hook, def, name) \
  MB2CO_TEST_ASSIGNABLE_##access(t, flags, id)
#define MB2CO_TEST_S_NONE(index, sub, id, access, hook, cap, text, name)
MB2CO_GATEWAY_OD(MB2CO_TEST_N_ASSIGNABLE, MB2CO_TEST_S_NONE)

static_assert(sizeof(PdoMapped<uint8_t>) == 1 && sizeof(PdoMapped<uint16_t>) == 2 &&
                  sizeof(PdoMapped<uint32_t>) == 4,
              "the OD reaches a PdoMapped entry by byte offset");

// The keys in list order: each names the row at its position.
#define MB2CO_TEST_N_KEY(index, sub, id, t, access, flags, hook, def, name) e::id,
#define MB2CO_TEST_S_KEY(index, sub, id, access, hook, cap, text, name) e::id,
const OdKey kKeys[] = {MB2CO_GATEWAY_OD(MB2CO_TEST_N_KEY, MB2CO_TEST_S_KEY)};

TEST(OdNames, EveryKeyFindsItsOwnRow) {
  GatewayValues values{};
  ObjectDictionary od(gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values));
  ASSERT_EQ(sizeof kKeys / sizeof kKeys[0], od.row_count());
  for (uint16_t row = 0; row < od.row_count(); ++row) {
    EXPECT_EQ(od.find(kKeys[row]), row) << od.definition().names[row];
  }
}

TEST(OdNames, KeysCarryTheMappingLengthOfTheirType) {
  EXPECT_EQ(e::x2100_2_runState.map_entry(), 0x21000208u);
  EXPECT_EQ(e::x2100_3_stop2Count.map_entry(), 0x21000310u);
  EXPECT_EQ(e::x2140_1_startPressed.bits, 1u);  // BOOLEAN
  EXPECT_EQ(e::x2300_1_buttonEdgeUs.bits, 32u);
  EXPECT_EQ(e::x1008_0_deviceName.bits, 0u);  // a string
}

TEST(OdNames, ValueBlockMembersAreTheOdsValues) {
  GatewayValues values{};
  ObjectDictionary od(gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values));
  od.restore_defaults(0x0000, 0xFFFF);
  EXPECT_EQ(values.x1017_0_producerHeartbeatTime, od.get(od.find(e::x1017_0_producerHeartbeatTime)));
  EXPECT_EQ(values.x2000_9_modbusWatchdogMs, 2000u);
  const uint8_t run = 1;
  ASSERT_EQ(od.write(0x2110, 1, &run, 1), kSdoOk);
  EXPECT_EQ(values.x2110_1_prevRunState, 1u);
}

TEST(OdNames, PutChangesTheRevisionExactlyWhenTheValueChanges) {
  GatewayValues values{};
  ObjectDictionary od(gateway::od::GatewayDefinition, reinterpret_cast<uint8_t*>(&values));
  const uint16_t r0 = od.revision();
  od.put(values.x2100_3_stop2Count, 0u);  // as before: TPDOs have nothing new
  EXPECT_EQ(od.revision(), r0);
  od.put(values.x2100_3_stop2Count, 7u);
  EXPECT_EQ(od.revision(), static_cast<uint16_t>(r0 + 1u));
  EXPECT_EQ(values.x2100_3_stop2Count, 7u);
  EXPECT_EQ(od.get(od.find(e::x2100_3_stop2Count)), 7u);
  od.put(values.x2100_2_runState, 1u);  // the byte-sized path (out of line)
  EXPECT_EQ(od.revision(), static_cast<uint16_t>(r0 + 2u));
  od.put(values.x2100_2_runState, 1u);
  EXPECT_EQ(od.revision(), static_cast<uint16_t>(r0 + 2u));
}

// Black box: with the event timers off, a TPDO goes out only because the OD
// told it of a change. Every PDO-mapped entry the line application changes
// by itself must reach the bus at once.
TEST(OdNames, LineAppChangesReachTheTpdosWithoutAnEventTimer) {
  test::Line line(2, [](ObjectDictionary& od, int) {
    const uint8_t zero[2] = {0, 0};
    ASSERT_EQ(od.write(0x1800, 5, zero, 2), kSdoOk);  // TPDO1 line state: no refresh
    ASSERT_EQ(od.write(0x1801, 5, zero, 2), kSdoOk);  // TPDO2 buttons
    ASSERT_EQ(od.write(0x2000, 9, zero, 2), kSdoOk);  // no Modbus watchdog
  });
  line.run_ms(500);
  ASSERT_EQ(line.od_get(0, 0x2002, 0), kNmtOperational);
  auto last_from_0 = [&line](uint16_t cob) -> const CanFrame* {
    const CanFrame* f = nullptr;
    for (const test::Line::Sent& s : line.log) {
      if (s.from == 0 && s.frame.id == cob) f = &s.frame;
    }
    return f;
  };

  line.log.clear();
  const uint8_t run = 1;
  ASSERT_EQ(line.gw(0).od().write(0x2100, 1, &run, 1), kSdoOk);
  line.run_ms(5);
  const CanFrame* tpdo1 = last_from_0(0x181);
  ASSERT_NE(tpdo1, nullptr) << "RUN state 2100h/2 changed, TPDO1 silent";
  EXPECT_EQ(tpdo1->data[0], 1u);

  line.log.clear();
  line.station(0).buttons = gateway::kStop2;
  line.run_ms(40);  // past the debounce time (20 ms)
  const CanFrame* tpdo2 = last_from_0(0x281);
  ASSERT_NE(tpdo2, nullptr) << "buttons 6000h/1 changed, TPDO2 silent";
  EXPECT_EQ(tpdo2->data[0], gateway::kStop2);
  tpdo1 = last_from_0(0x181);
  ASSERT_NE(tpdo1, nullptr) << "STOP2 counter 2100h/3 and RUN state changed, TPDO1 silent";
  EXPECT_EQ(tpdo1->data[0], 0u);                       // stopped
  EXPECT_EQ(tpdo1->data[1] | tpdo1->data[2] << 8, 1);  // one STOP2 event
}

}  // namespace
}  // namespace mb2co
