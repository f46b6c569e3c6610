// The gateway's PDO records (1400h-1BFFh) kept as one template record per
// kind (od_define.h): every row reads as the list says, and what a master
// does with the records of PDO 2-4 lands in that PDO's own values.
#include <gtest/gtest.h>

#include "canopen/od.h"
#include "gateway/gateway_od.h"
#include "od_rows_as_listed.h"

namespace mb2co {
namespace {

using namespace canopen;  // the list's flags and hooks read unqualified
using gateway::od::GatewayDefinition;
using gateway::od::GatewayValues;

#define MB2CO_LISTED_VALUES GatewayValues
const test::ListedRow kGatewayRows[] = {MB2CO_GATEWAY_OD(MB2CO_LISTED_N, MB2CO_LISTED_S)};
#undef MB2CO_LISTED_VALUES

class OdRecords : public ::testing::Test {
 protected:
  GatewayValues values{};
  ObjectDictionary od{GatewayDefinition, reinterpret_cast<uint8_t*>(&values)};
};

TEST_F(OdRecords, EveryRowReadsAsItsListLine) {
  test::expect_rows_as_listed(od, kGatewayRows, sizeof kGatewayRows / sizeof kGatewayRows[0],
                              reinterpret_cast<const uint8_t*>(&values));
}

TEST_F(OdRecords, TheGatewayKeepsOneTemplateRecordPerKind) {
  EXPECT_EQ(GatewayDefinition.record_count, 4u * (5u + 5u + 6u + 5u));
  EXPECT_EQ(od.find(0x1400, 0), GatewayDefinition.record_first);
  EXPECT_EQ(od.index_of(static_cast<uint16_t>(GatewayDefinition.record_first - 1u)), 0x1200u);
  EXPECT_EQ(
      od.index_of(static_cast<uint16_t>(GatewayDefinition.record_first + GatewayDefinition.record_count)),
      0x2000u);
}

// A master configures TPDO3 and RPDO4 by SDO as CiA 301 asks (disable, map,
// enable): each write reaches that PDO's own members, none of PDO 1's.
TEST_F(OdRecords, WritesToTheRecordsOfPdo2To4ReachTheirOwnValues) {
  od.set_node_id(2);
  od.restore_defaults(0x0000, 0xFFFF);
  const uint8_t event[2] = {0x2C, 0x01};  // 300 ms
  ASSERT_EQ(od.write(0x1802, 5, event, 2), kSdoOk);
  EXPECT_EQ(values.x1802_5_eventTimer, 300u);
  EXPECT_EQ(values.x1800_5_eventTimer, 100u);
  const uint8_t zero = 0;
  ASSERT_EQ(od.write(0x1A02, 0, &zero, 1), kSdoOk);
  const uint8_t entry[4] = {0x08, 0x02, 0x00, 0x21};  // 2100h/2, 8 bits
  ASSERT_EQ(od.write(0x1A02, 1, entry, 4), kSdoOk);
  EXPECT_EQ(values.x1A02_1_mappedObject1, 0x21000208u);
  EXPECT_EQ(values.x1A00_1_mappedObject1, 0x21000208u);  // TPDO1's own default
  EXPECT_EQ(values.x1A01_1_mappedObject1, 0x60000108u);
  const uint8_t cob[4] = {0x05, 0x03, 0x00, 0x00};  // 305h, valid
  ASSERT_EQ(od.write(0x1403, 1, cob, 4), kSdoOk);
  EXPECT_EQ(values.x1403_1_cobId, 0x305u);
  uint8_t back[4] = {};
  uint16_t len = 0;
  ASSERT_EQ(od.read(0x1403, 1, back, sizeof back, &len), kSdoOk);
  EXPECT_EQ(len, 4u);
  EXPECT_EQ(le32(back), 0x305u);
  // Sub 4 of a communication record is CiA 301's reserved entry: absent.
  EXPECT_EQ(od.read(0x1403, 4, back, sizeof back, &len), kAbortNoSubindex);
  EXPECT_EQ(od.read(0x1404, 0, back, sizeof back, &len), kAbortNoObject);
}

TEST_F(OdRecords, EveryRecordRowHasItsOwnDefault) {
  od.set_node_id(2);
  od.restore_defaults(0x0000, 0xFFFF);
  EXPECT_EQ(values.x1400_1_cobId, 0x17Fu + 2u);
  EXPECT_EQ(values.x1401_1_cobId, 0x181u + 2u);
  EXPECT_EQ(values.x1402_1_cobId, 0x27Fu + 2u);
  EXPECT_EQ(values.x1403_1_cobId, 0x80000500u + 2u);
  EXPECT_EQ(values.x1800_3_inhibitTime, 100u);
  EXPECT_EQ(values.x1801_3_inhibitTime, 0u);
  EXPECT_EQ(values.x1601_2_mappedObject2, 0x00060010u);  // a dummy entry
  EXPECT_EQ(values.x1602_0_mappedCount, 1u);
  EXPECT_EQ(values.x1603_0_mappedCount, 0u);
}

}  // namespace
}  // namespace mb2co
