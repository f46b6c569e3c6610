// Issue 16 item 6: damaged saved parameters are reported, on the gateway as
// the Uno runs it (a 1 KiB EEPROM): every kind of damaged image starts with
// the defaults or the older set, and says so by EMCY 5530h after the boot-up,
// 1001h bit 0 and the counter 2003h, both read over Modbus (FC 04); a blank
// EEPROM (nothing saved) says nothing. Starting never writes the EEPROM.
#include <gtest/gtest.h>

#include "gateway/register_map.h"
#include "line_harness.h"
#include "modbus/master_codec.h"
#include "storage_damage.h"

namespace mb2co {
namespace {

using test::Line;
namespace sd = test::storage_damage;
namespace e = gateway::od::GatewayEntry;

const uint16_t kIrDamageCount =
    gateway::default_address(modbus::Table::kInputRegisters, e::x2003_0_storageDamageCount);
const uint16_t kIrErrorRegister =
    gateway::default_address(modbus::Table::kInputRegisters, e::x1001_0_errorRegister);
static_assert(gateway::default_address(modbus::Table::kInputRegisters, e::x2003_0_storageDamageCount) !=
                  0xFFFF,
              "the counter is in the default input map");

void write_u8(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub, uint8_t v) {
  ASSERT_EQ(od.write(index, sub, &v, 1), canopen::kSdoOk) << std::hex << index;
}
void write_u16(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub, uint16_t v) {
  uint8_t b[2];
  canopen::put_le16(b, v);
  ASSERT_EQ(od.write(index, sub, b, 2), canopen::kSdoOk) << std::hex << index;
}
/// "save", answered at once, then the passes that write it (Node::saving).
void save(gateway::Gateway& gw, uint32_t now_us) {
  uint8_t b[4];
  canopen::put_le32(b, canopen::kSaveSignature);
  ASSERT_EQ(gw.od().write(0x1010, 1, b, 4), canopen::kSdoOk);
  while (gw.node().saving()) gw.process(now_us, 0);
}

/// One station whose EEPROM holds set A (node id 9) in slot 0 and the newer
/// set B (node id 12) in slot 1, both with the marker debounce.
struct Station {
  Line line{1, [](canopen::ObjectDictionary& od, int) {
              write_u8(od, 0x2000, 1, 9);
              write_u16(od, 0x2000, 6, sd::kMarker);
            }};
  Station() {
    write_u8(line.gw(0).od(), 0x2000, 1, 12);
    save(line.gw(0), line.now_us);
  }
  std::vector<uint8_t>& eeprom() { return line.station(0).eeprom; }

  /// Input registers over Modbus (FC 04), the slave at address 1.
  uint16_t input_register(uint16_t address) {
    uint8_t req[8];
    const uint16_t n =
        modbus::build_read_request(req, sizeof req, 1, modbus::fc::kReadInputRegisters, address, 1);
    const std::vector<uint8_t> rsp = line.modbus(0, req, n);
    modbus::Response r;
    if (modbus::parse_response(req, n, rsp.data(), static_cast<uint16_t>(rsp.size()), r) !=
        modbus::ParseStatus::kOk)
      return 0xFFFF;
    return r.reg(0);
  }
  /// EMCY frames (COB-ID 1014h) sent since log entry `from`, after the boot-up.
  std::vector<CanFrame> emcy_after_boot_up(size_t from) {
    std::vector<CanFrame> out;
    const uint32_t emcy_id = line.od_get(0, 0x1014, 0) & 0x7FFu;
    bool booted = false;
    for (size_t i = from; i < line.log.size(); ++i) {
      const CanFrame& f = line.log[i].frame;
      if (f.id == 0x700u + line.gw(0).node_id() && f.dlc == 1 && f.data[0] == 0) booted = true;
      if (f.id == emcy_id) {
        EXPECT_TRUE(booted) << "EMCY before the boot-up message";
        out.push_back(f);
      }
    }
    return out;
  }
};

TEST(StorageReport, TheGoodImageLoadsTheNewerSetAndReportsNothing) {
  Station s;
  const size_t from = s.line.log.size();
  s.line.power_on(0);
  s.line.run_ms(50);
  EXPECT_EQ(s.line.gw(0).node_id(), 12);
  EXPECT_TRUE(s.emcy_after_boot_up(from).empty());
  EXPECT_EQ(s.input_register(kIrDamageCount), 0u);
  EXPECT_EQ(s.input_register(kIrErrorRegister) & 1u, 0u);
}

TEST(StorageReport, EveryKindOfDamageStartsSafelyAndIsReported) {
  for (const sd::Kind& kind : sd::kinds()) {
    SCOPED_TRACE(kind.name);
    Station s;
    std::vector<uint8_t> image = s.eeprom();
    ASSERT_TRUE(kind.apply(image));
    image.resize(1024, 0xFF);  // an EEPROM: what a cut file lacks reads erased
    s.eeprom() = image;
    const size_t from = s.line.log.size();
    s.line.power_on(0);
    s.line.run_ms(50);
    EXPECT_EQ(s.eeprom(), image) << "starting wrote the EEPROM";
    const uint8_t want_id = kind.verdict == sd::Verdict::kOlderSet ? 9 : 1;
    EXPECT_EQ(s.line.gw(0).node_id(), want_id);
    EXPECT_EQ(s.line.od_get(0, 0x2000, 6), kind.verdict == sd::Verdict::kOlderSet ? sd::kMarker : 20u)
        << "a damaged set is refused whole";
    const std::vector<CanFrame> emcy = s.emcy_after_boot_up(from);
    if (kind.verdict == sd::Verdict::kNoSet) {
      EXPECT_TRUE(emcy.empty()) << "a blank EEPROM is no damage";
      EXPECT_EQ(s.input_register(kIrDamageCount), 0u);
      EXPECT_EQ(s.input_register(kIrErrorRegister) & 1u, 0u);
      continue;
    }
    ASSERT_EQ(emcy.size(), 1u);
    EXPECT_EQ(emcy[0].data[0] | (emcy[0].data[1] << 8), 0x5530);
    EXPECT_EQ(emcy[0].data[2] & 1u, 1u) << "1001h bit 0 in the EMCY";
    EXPECT_EQ(s.input_register(kIrDamageCount), 1u);
    EXPECT_EQ(s.input_register(kIrErrorRegister) & 1u, 1u);
  }
}

// The counter counts resets that found damage (not frames or reads), and a
// good save clears the error but not the count.
TEST(StorageReport, TheCounterCountsEveryResetThatFindsDamage) {
  Station s;
  s.eeprom()[sd::kSlot + sd::kHeader + 20] ^= 0x01;  // the newer set damaged
  s.line.power_on(0);
  s.line.run_ms(50);
  ASSERT_EQ(s.input_register(kIrDamageCount), 1u);
  write_u8(s.line.gw(0).od(), 0x2001, 0, 2);  // restart request: reset node, loads again
  s.line.run_ms(50);
  EXPECT_EQ(s.input_register(kIrDamageCount), 2u);
  EXPECT_EQ(s.line.gw(0).node_id(), 9);
  save(s.line.gw(0), s.line.now_us);
  s.line.run_ms(10);
  EXPECT_EQ(s.input_register(kIrErrorRegister) & 1u, 0u) << "a good save ends the error";
  EXPECT_EQ(s.input_register(kIrDamageCount), 2u) << "the count never goes down";
}

/// Writes that fail from the n-th on: power lost in the middle of a save.
struct CutPower {
  static int writes_left;
  static bool (*write)(void*, uint16_t, const uint8_t*, uint16_t);
  static bool refused;
  static bool cut_write(void* ctx, uint16_t at, const uint8_t* data, uint16_t n) {
    refused = refused || writes_left == 0;
    if (writes_left == 0) return false;
    --writes_left;
    return write(ctx, at, data, n);
  }
};
int CutPower::writes_left = 0;
bool CutPower::refused = false;
bool (*CutPower::write)(void*, uint16_t, const uint8_t*, uint16_t) = nullptr;

// A save after damage was found writes into the damaged slot, not over the
// only valid set: power lost at any write of that save still leaves set A
// (or the new set) to load, never the defaults.
TEST(StorageReport, ASaveCutOffAfterDamageNeverLosesTheValidSet) {
  int writes = 0;
  for (int cut = 0;; ++cut) {
    SCOPED_TRACE(cut);
    Station s;
    s.eeprom()[sd::kSlot + sd::kHeader + 20] ^= 0x01;  // the newer set damaged
    s.line.power_on(0);
    s.line.run_ms(20);
    ASSERT_EQ(s.line.gw(0).node_id(), 9);
    canopen::ParamStorage& storage = s.line.station(0).storage;
    CutPower::write = storage.write;
    CutPower::writes_left = cut;
    storage.write = &CutPower::cut_write;
    write_u8(s.line.gw(0).od(), 0x2000, 1, 7);
    uint8_t b[4];
    canopen::put_le32(b, canopen::kSaveSignature);
    CutPower::refused = false;
    ASSERT_EQ(s.line.gw(0).od().write(0x1010, 1, b, 4), canopen::kSdoOk) << "answered before it runs";
    while (s.line.gw(0).node().saving()) s.line.gw(0).process(s.line.now_us, 0);
    const bool saved = !CutPower::refused;
    storage.write = CutPower::write;
    s.line.power_on(0);
    s.line.run_ms(20);
    const uint8_t id = s.line.gw(0).node_id();
    EXPECT_TRUE(id == 9 || id == 7) << "node id " << int(id) << " after a save cut at write " << cut;
    if (saved) {
      EXPECT_EQ(id, 7);
      writes = cut;
      break;
    }
  }
  EXPECT_GT(writes, 3) << "a save is several writes";
}

}  // namespace
}  // namespace mb2co
