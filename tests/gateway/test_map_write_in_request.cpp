// A Modbus request that writes a map entry (2400h-2403h) on its way: the
// rest of the request follows the map as it is now when the written map is
// the request's own, and is unaffected when it is another table's.
#include <gtest/gtest.h>

#include "line_harness.h"

namespace mb2co {
namespace {

using test::Line;

class MapWriteInRequest : public ::testing::Test {
 protected:
  Line line{1};
  void SetUp() override { line.run_ms(50); }
  void sdo_map(uint8_t sub, uint32_t entry) {
    uint8_t b[4];
    canopen::put_le32(b, entry);
    ASSERT_EQ(line.gw(0).od().write(0x2400, sub, b, 4), canopen::kSdoOk);
  }
  /// FC 10h from holding register 0; true when answered without exception.
  bool write_from_0(std::vector<uint16_t> v) {
    uint8_t req[64];
    const uint16_t n =
        modbus::build_write_registers(req, sizeof req, 1, 0, static_cast<uint16_t>(v.size()), v.data());
    const std::vector<uint8_t> raw = line.modbus(0, req, n);
    modbus::Response rsp;
    return !raw.empty() && modbus::parse_response(req, n, raw.data(), static_cast<uint16_t>(raw.size()),
                                                  rsp) == modbus::ParseStatus::kOk;
  }
};

TEST_F(MapWriteInRequest, OwnMapWrittenFirstMovesTheRestOfTheRequest) {
  sdo_map(1, MB2CO_PDO_MAP_ENTRY(0x2400, 2, 32));  // HR 0-1: the entry of HR 2 itself
  const uint32_t station_count = MB2CO_PDO_MAP_ENTRY(0x2000, 4, 8);
  ASSERT_TRUE(
      write_from_0({static_cast<uint16_t>(station_count >> 16), static_cast<uint16_t>(station_count), 3}));
  EXPECT_EQ(line.od_get(0, 0x2400, 2), station_count);
  EXPECT_EQ(line.od_get(0, 0x2000, 4), 3u) << "HR 2 is the station count now";
  EXPECT_EQ(line.od_get(0, 0x6200, 1), 0u) << "the lab LED HR 2 mapped before stays";
}

TEST_F(MapWriteInRequest, OwnMapEntryRewrittenByItselfLaysOutTheRestAnew) {
  sdo_map(1, MB2CO_PDO_MAP_ENTRY(0x2400, 1, 32));  // HR 0-1: this very entry
  // Now HR 0 is the RUN command (one register): HR 1 the lab LED, HR 2 the
  // node id (the default map's second and third entries).
  const uint32_t run_command = MB2CO_PDO_MAP_ENTRY(0x2100, 1, 8);
  ASSERT_TRUE(
      write_from_0({static_cast<uint16_t>(run_command >> 16), static_cast<uint16_t>(run_command), 5}));
  EXPECT_EQ(line.od_get(0, 0x2400, 1), run_command);
  EXPECT_EQ(line.od_get(0, 0x2000, 1), 5u) << "HR 2 is the node id in the new layout";
  EXPECT_EQ(line.od_get(0, 0x6200, 1), 0u);
}

TEST_F(MapWriteInRequest, AnotherTablesMapLeavesTheRequestAsItWas) {
  sdo_map(1, MB2CO_PDO_MAP_ENTRY(0x2401, 1, 32));  // HR 0-1: input register 0's entry
  const uint32_t run_state = MB2CO_PDO_MAP_ENTRY(0x2100, 2, 8);
  ASSERT_TRUE(write_from_0({static_cast<uint16_t>(run_state >> 16), static_cast<uint16_t>(run_state), 1}));
  EXPECT_EQ(line.od_get(0, 0x2401, 1), run_state);
  EXPECT_EQ(line.od_get(0, 0x6200, 1), 1u) << "HR 2 is still the lab LED";
}

}  // namespace
}  // namespace mb2co
