// The wider types through the gateway's Modbus maps, as on mb2co-node (the
// host build: MB2CO_CONFIG_WIDE_TYPES): a REAL32 written as two holding
// registers and an UNSIGNED64 as four go out in TPDO3/TPDO4 and read back by
// SDO with the same bits; a write of several registers is all or nothing;
// a string is a register run.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "gateway/register_map.h"
#include "line_harness.h"
#include "value_bytes.h"

namespace mb2co {
namespace {

using modbus::Exception;
using modbus::ParseStatus;
using modbus::Response;
using test::bits_of;
using test::le_bytes;
using test::Line;
namespace entry = gateway::od::GatewayEntry;

static_assert(MB2CO_CONFIG_WIDE_TYPES, "host builds carry the wide types");

// Where the default holding map puts the process values of 2500h.
constexpr uint16_t kHrReal =
    gateway::default_address(modbus::Table::kHoldingRegisters, entry::x2500_1_measuredValue);
constexpr uint16_t kHrCounter =
    gateway::default_address(modbus::Table::kHoldingRegisters, entry::x2500_2_eventCounter);
static_assert(kHrCounter == kHrReal + 2, "REAL32: two registers");

class WideRegisters : public ::testing::Test {
 protected:
  Line line{1};
  uint8_t req[260] = {};
  std::vector<uint8_t> raw;  ///< the last response (rsp points into it)
  Response rsp{};

  void SetUp() override { line.run_ms(50); }

  ParseStatus call(uint16_t len) {
    raw = line.modbus(0, req, len);
    if (raw.empty()) return ParseStatus::kTooShort;
    return modbus::parse_response(req, len, raw.data(), static_cast<uint16_t>(raw.size()), rsp);
  }
  ParseStatus write_registers(uint16_t start, std::vector<uint16_t> v) {
    return call(
        modbus::build_write_registers(req, sizeof req, 1, start, static_cast<uint16_t>(v.size()), v.data()));
  }
  ParseStatus read(uint8_t fc, uint16_t start, uint16_t n) {
    return call(modbus::build_read_request(req, sizeof req, 1, fc, start, n));
  }
  /// The frames station 0 sent since `from` (an index into line.log) with this id.
  std::vector<CanFrame> sent(size_t from, uint32_t id) {
    std::vector<CanFrame> out;
    for (size_t i = from; i < line.log.size(); ++i) {
      if (line.log[i].from == 0 && line.log[i].frame.id == id) out.push_back(line.log[i].frame);
    }
    return out;
  }
  /// One SDO request to the gateway (node 1) on the bus; its answer.
  CanFrame sdo(std::initializer_list<uint8_t> data) {
    CanFrame f{};
    f.id = 0x601;
    f.dlc = 8;
    uint8_t i = 0;
    for (uint8_t b : data) f.data[i++] = b;
    const size_t from = line.log.size();
    line.gw(0).on_can_frame(f, line.now_us);
    line.run_ms(1);
    const std::vector<CanFrame> r = sent(from, 0x581);
    EXPECT_EQ(r.size(), 1u);
    return r.empty() ? CanFrame{} : r[0];
  }
  /// SDO upload from the gateway over CAN (expedited or segmented): the bytes.
  std::vector<uint8_t> sdo_upload(uint16_t index, uint8_t sub) {
    const CanFrame init = sdo({0x40, static_cast<uint8_t>(index), static_cast<uint8_t>(index >> 8), sub});
    std::vector<uint8_t> out;
    if (init.data[0] & 0x02) {  // expedited
      const uint8_t n = (init.data[0] & 0x01) ? static_cast<uint8_t>(4 - ((init.data[0] >> 2) & 3)) : 4;
      return std::vector<uint8_t>(&init.data[4], &init.data[4] + n);
    }
    EXPECT_EQ(init.data[0], 0x41) << "segmented upload";
    uint8_t toggle = 0;
    for (int guard = 0; guard < 16; ++guard) {
      const CanFrame s = sdo({static_cast<uint8_t>(0x60 | toggle)});
      const uint8_t n = static_cast<uint8_t>(7 - ((s.data[0] >> 1) & 7));
      out.insert(out.end(), &s.data[1], &s.data[1] + n);
      toggle ^= 0x10;
      if (s.data[0] & 0x01) break;
    }
    EXPECT_EQ(out.size(), canopen::le32(&init.data[4]));
    return out;
  }
  /// Enables TPDO3 (REAL32) and TPDO4 (UNSIGNED64) at their default COB-IDs
  /// (380h/480h + node id): their mappings are in place by default.
  void enable_tpdos() {
    uint8_t cob[4];
    canopen::put_le32(cob, 0x381);
    ASSERT_EQ(line.gw(0).od().write(0x1802, 1, cob, 4), canopen::kSdoOk);
    canopen::put_le32(cob, 0x481);
    ASSERT_EQ(line.gw(0).od().write(0x1803, 1, cob, 4), canopen::kSdoOk);
    line.run_ms(5);
  }
  /// FC 10h of a REAL32's two registers (high word first); then TPDO3 and
  /// an SDO upload carry the same bits.
  void expect_real32_round_trip(float f) {
    const uint32_t bits = bits_of(f);
    const size_t from = line.log.size();
    ASSERT_EQ(write_registers(kHrReal, {static_cast<uint16_t>(bits >> 16), static_cast<uint16_t>(bits)}),
              ParseStatus::kOk);
    line.run_ms(5);
    const std::vector<CanFrame> tpdo = sent(from, 0x381);
    ASSERT_EQ(tpdo.size(), 1u) << "one TPDO3 for the change";
    EXPECT_EQ(tpdo[0].dlc, 4);
    EXPECT_EQ(std::vector<uint8_t>(tpdo[0].data, tpdo[0].data + 4), le_bytes(bits, 4));
    EXPECT_EQ(sdo_upload(0x2500, 1), le_bytes(bits, 4));
    ASSERT_EQ(read(modbus::fc::kReadHoldingRegisters, kHrReal, 2), ParseStatus::kOk);
    EXPECT_EQ(rsp.reg(0), bits >> 16);
    EXPECT_EQ(rsp.reg(1), bits & 0xFFFFu);
  }
};

TEST_F(WideRegisters, Real32WrittenAsTwoRegistersGoesOutInTpdoAndReadsBackBySdo) {
  enable_tpdos();
  expect_real32_round_trip(-1234.5625f);  // C49A5200h
  expect_real32_round_trip(1.0e-40f);     // a subnormal (000116C2h)
  expect_real32_round_trip(-0.75f);
}

TEST_F(WideRegisters, Unsigned64WrittenAsFourRegistersGoesOutInTpdoAndReadsBackBySdo) {
  enable_tpdos();
  const uint64_t v = 0x0123456789ABCDEFULL;
  const size_t from = line.log.size();
  ASSERT_EQ(write_registers(kHrCounter, {0x0123, 0x4567, 0x89AB, 0xCDEF}), ParseStatus::kOk);
  line.run_ms(5);
  const std::vector<CanFrame> tpdo = sent(from, 0x481);
  ASSERT_EQ(tpdo.size(), 1u);
  EXPECT_EQ(tpdo[0].dlc, 8);
  EXPECT_EQ(std::vector<uint8_t>(tpdo[0].data, tpdo[0].data + 8), le_bytes(v, 8));
  EXPECT_EQ(sdo_upload(0x2500, 2), le_bytes(v, 8));
  ASSERT_EQ(read(modbus::fc::kReadHoldingRegisters, kHrCounter, 4), ParseStatus::kOk);
  EXPECT_EQ(rsp.reg(0), 0x0123u);
  EXPECT_EQ(rsp.reg(3), 0xCDEFu);
}

TEST_F(WideRegisters, SeveralRegistersAreWrittenWholeOrNotAtAll) {
  ASSERT_EQ(write_registers(kHrReal, {0xC49A, 0x5200, 0, 0, 0, 42}), ParseStatus::kOk);
  // Part of the 64-bit value: no address of it is written (02).
  ASSERT_EQ(write_registers(kHrCounter, {1, 2}), ParseStatus::kException);
  EXPECT_EQ(rsp.exception, Exception::kIllegalDataAddress);
  ASSERT_EQ(write_registers(kHrCounter + 1, {1, 2, 3}), ParseStatus::kException);
  EXPECT_EQ(rsp.exception, Exception::kIllegalDataAddress);
  // A REAL32 beyond its limits (+-1e6) refuses the request: the counter in
  // the same request keeps its value too (04).
  const uint32_t two_million = bits_of(2.0e6f);
  ASSERT_EQ(write_registers(kHrReal, {static_cast<uint16_t>(two_million >> 16),
                                      static_cast<uint16_t>(two_million), 9, 9, 9, 9}),
            ParseStatus::kException);
  EXPECT_EQ(rsp.exception, Exception::kServerDeviceFailure);
  const uint32_t nan = 0x7FC00000u;
  ASSERT_EQ(write_registers(kHrReal, {static_cast<uint16_t>(nan >> 16), 0, 9, 9, 9, 9}),
            ParseStatus::kException);
  ASSERT_EQ(read(modbus::fc::kReadHoldingRegisters, kHrReal, 6), ParseStatus::kOk);
  EXPECT_EQ(rsp.reg(0), 0xC49Au);
  EXPECT_EQ(rsp.reg(1), 0x5200u);
  EXPECT_EQ(rsp.reg(5), 42u);
  EXPECT_EQ(sdo_upload(0x2500, 2), le_bytes(42, 8));
}

TEST_F(WideRegisters, AStringIsARunOfRegistersTwoCharactersEach) {
  // The device name (1008h, "mb2co gateway", 13 characters) in place of
  // the last input register entry: 7 registers, the last one padded.
  const uint16_t address =
      gateway::default_address(modbus::Table::kInputRegisters, canopen::OdKey{0x2003, 0, 8});
  uint8_t map_entry[4];
  canopen::put_le32(map_entry, MB2CO_PDO_MAP_ENTRY(0x1008, 0, 112));
  ASSERT_EQ(line.gw(0).od().write(0x2401, gateway::kInputMapSize, map_entry, 4), canopen::kSdoOk);
  ASSERT_EQ(read(modbus::fc::kReadInputRegisters, address, 7), ParseStatus::kOk);
  const char* expected = "mb2co gateway";
  for (uint16_t k = 0; k < 7; ++k) {
    const uint16_t hi = static_cast<uint8_t>(expected[2 * k]);
    const uint16_t lo = 2 * k + 1 < 13 ? static_cast<uint8_t>(expected[2 * k + 1]) : 0;
    EXPECT_EQ(rsp.reg(k), (hi << 8) | lo) << k;
  }
  // A run must cover the whole string, 16 bits per two characters.
  canopen::put_le32(map_entry, MB2CO_PDO_MAP_ENTRY(0x1008, 0, 96));
  EXPECT_EQ(line.gw(0).od().write(0x2401, gateway::kInputMapSize, map_entry, 4), canopen::kAbortInvalidValue);
  // 64 bits of the REAL32, 32 of the UNSIGNED64: not their length.
  canopen::put_le32(map_entry, MB2CO_PDO_MAP_ENTRY(0x2500, 1, 64));
  EXPECT_EQ(line.gw(0).od().write(0x2400, 1, map_entry, 4), canopen::kAbortInvalidValue);
  canopen::put_le32(map_entry, MB2CO_PDO_MAP_ENTRY(0x2500, 2, 32));
  EXPECT_EQ(line.gw(0).od().write(0x2400, 1, map_entry, 4), canopen::kAbortInvalidValue);
}

}  // namespace
}  // namespace mb2co
