// Storing parameters (1010h "save", 1011h "load" = restore defaults) through
// a RAM-backed ParamStorage, and what survives which reset.
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

/// Byte-addressed storage in RAM; can be told to fail from the n-th write on.
struct RamStorage {
  std::vector<uint8_t> mem = std::vector<uint8_t>(1024, 0xFF);
  int writes_left = -1;  ///< -1: never fail
  static bool read(void* ctx, uint16_t at, uint8_t* data, uint16_t len) {
    RamStorage& s = *static_cast<RamStorage*>(ctx);
    if (static_cast<size_t>(at) + len > s.mem.size()) return false;
    memcpy(data, &s.mem[at], len);
    return true;
  }
  static bool write(void* ctx, uint16_t at, const uint8_t* data, uint16_t len) {
    RamStorage& s = *static_cast<RamStorage*>(ctx);
    if (s.writes_left == 0 || static_cast<size_t>(at) + len > s.mem.size()) return false;
    if (s.writes_left > 0) --s.writes_left;
    memcpy(&s.mem[at], data, len);
    return true;
  }
  ParamStorage api() { return ParamStorage{&RamStorage::read, &RamStorage::write, nullptr, this}; }
};

class Storage : public IoNodeTest {
 protected:
  void SetUp() override {
    io.node().set_storage(&api);
    IoNodeTest::SetUp();
  }
  void configure() {
    ASSERT_EQ(h.write_u16(0x1017, 0, 250), 0u);
    ASSERT_EQ(h.write_u16(0x2101, 0, 42), 0u);
    ASSERT_EQ(h.download(0x2000, 0, bytes_of("line 2, station 3")), 0u);
    ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
    ASSERT_EQ(h.write_u8(0x1800, 2, 1), 0u);
  }
  void expect_configured() {
    EXPECT_EQ(h.read(0x1017, 0), 250u);
    EXPECT_EQ(h.read(0x2101, 0), 42u);
    EXPECT_EQ(h.read_string(0x2000, 0), "line 2, station 3");
    EXPECT_EQ(h.read(0x1800, 1), 0x80000183u);
    EXPECT_EQ(h.read(0x1800, 2), 1u);
  }
  void expect_defaults() {
    EXPECT_EQ(h.read(0x1017, 0), 0u);
    EXPECT_EQ(h.read(0x2101, 0), 10u);
    EXPECT_EQ(h.read_string(0x2000, 0), "");
    EXPECT_EQ(h.read(0x1800, 1), 0x183u);
    EXPECT_EQ(h.read(0x1800, 2), 255u);
  }
  RamStorage ram;
  ParamStorage api = ram.api();
};

TEST_F(Storage, CapabilityReadsOne) {
  EXPECT_EQ(h.read(0x1010, 1), 1u);
}

TEST_F(Storage, SavedParametersSurviveResetNode) {
  configure();
  EXPECT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  EXPECT_EQ(h.read(0x1010, 1), 1u) << "the signature is not stored";
  h.nmt(0x81, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  expect_configured();
  EXPECT_TRUE(io.node().params_loaded());
}

TEST_F(Storage, ResetCommunicationReloadsOnlyTheCommunicationArea) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);  // not saved
  ASSERT_EQ(h.write_u16(0x2101, 0, 77), 0u);   // not saved
  h.nmt(0x82, kId);
  EXPECT_EQ(h.read(0x1017, 0), 250u) << "communication area: saved value";
  EXPECT_EQ(h.read(0x2101, 0), 77u) << "application area untouched by reset communication";
}

TEST_F(Storage, RestoreDefaultsTakesEffectAtTheNextReset) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  ASSERT_EQ(h.write_u32(0x1011, 1, kLoadSignature), 0u);
  expect_configured();  // nothing changes until the reset
  h.nmt(0x81, kId);
  expect_defaults();
  EXPECT_FALSE(io.node().params_loaded());
}

TEST_F(Storage, AnInterruptedSaveLeavesDefaults) {
  configure();
  ram.writes_left = 3;  // dies in the middle of the payload
  const std::vector<Bytes> before = od_snapshot(od());
  h.expect_abort({0x23, 0x10, 0x10, 0x01, 's', 'a', 'v', 'e'}, 0x1010, 1, kAbortGeneral);
  EXPECT_TRUE(od_snapshot(od()) == before);
  ram.writes_left = -1;
  h.nmt(0x81, kId);
  expect_defaults();
}

TEST_F(Storage, ACorruptedImageIsIgnored) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  for (size_t at : {size_t{0}, size_t{5}, size_t{20}}) {
    RamStorage copy = ram;
    ram.mem[at] ^= 0x01;
    h.nmt(0x81, kId);
    expect_defaults();
    ram = copy;
    configure();
  }
  h.nmt(0x81, kId);
  expect_configured();
}

TEST_F(Storage, TheErrorHistoryIsNotSaved) {
  io.node().emcy().raise(0x5000, kErrDeviceProfile);
  h.advance_us(10);
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1003, 0), 0u);
}

// CRC-16/MODBUS bit by bit (poly A001h reflected, init FFFFh), written here
// independently of shared/modbus/crc16.cpp.
uint16_t crc16_bitwise(const uint8_t* p, size_t n, uint16_t crc = 0xFFFF) {
  for (size_t i = 0; i < n; ++i) {
    crc ^= p[i];
    for (int b = 0; b < 8; ++b)
      crc = (crc & 1u) ? static_cast<uint16_t>((crc >> 1) ^ 0xA001u) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

/// The CRC a slot carries: over its payload, then its header.
uint16_t slot_crc(const uint8_t* slot, size_t len) {
  return crc16_bitwise(slot, 6, crc16_bitwise(slot + 6, len));
}
constexpr size_t kSlotBytes = 512;  // slot k at k * 512: the Uno's EEPROM in halves

/// The layout of the saved image, recomputed from the OD: payload length
/// and the offset of (index, sub) in the payload.
size_t payload_bytes(const ObjectDictionary& od, uint16_t index = 0xFFFF, uint8_t sub = 0,
                     size_t* at = nullptr) {
  size_t n = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const OdEntry e = od.entry(r);
    if (e.index == index && e.sub == sub && at != nullptr) *at = n;
    if (param_is_saved(od, r)) n += od.capacity_of(r);
  }
  return n;
}

// Two slots at 0 and 512: magic "C2", sequence number, payload length,
// payload, and a CRC-16/MODBUS over payload and header (low byte first),
// checked here independently; saves alternate between the slots and count up.
TEST_F(Storage, EachSaveFillsTheOtherSlotWithACrcAndTheNextSequenceNumber) {
  configure();
  const size_t len = payload_bytes(od());
  ASSERT_LE(6 + len + 2, kSlotBytes) << "a slot holds the I/O node's set";
  for (unsigned save = 1; save <= 3; ++save) {
    ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
    const uint8_t* s = &ram.mem[((save - 1) % 2) * kSlotBytes];
    EXPECT_EQ(s[0], 0x43);
    EXPECT_EQ(s[1], 0x32);
    EXPECT_EQ(s[2] | (s[3] << 8), static_cast<int>(save)) << "sequence number";
    EXPECT_EQ(static_cast<size_t>(s[4] | (s[5] << 8)), len);
    const uint16_t crc = slot_crc(s, len);
    EXPECT_EQ(s[6 + len], crc & 0xFF);
    EXPECT_EQ(s[7 + len], crc >> 8);
  }
}

// A save cut off after any number of writes (power failure, kill -9) leaves
// the set saved before it in force: never the defaults.
TEST_F(Storage, ASaveCutOffAtAnyWriteKeepsThePreviousSet) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);  // set A: 1017h = 250
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);  // again: both slots hold A
  const RamStorage with_a = ram;
  int cut = 0;
  for (;; ++cut) {
    ram = with_a;
    ASSERT_EQ(h.write_u16(0x1017, 0, 500), 0u);  // set B
    ram.writes_left = cut;
    const bool saved = h.write_u32(0x1010, 1, kSaveSignature) == 0u;
    ram.writes_left = -1;
    h.nmt(0x81, kId);
    EXPECT_TRUE(io.node().params_loaded()) << "cut after " << cut << " writes: defaults";
    const uint32_t hb = h.read(0x1017, 0);
    EXPECT_TRUE(hb == 250u || hb == 500u) << "cut after " << cut << " writes: " << hb;
    if (saved) {
      EXPECT_EQ(hb, 500u) << "an answered save is in force";
      break;
    }
  }
  EXPECT_GT(cut, 10) << "the save was cut at every write it makes";
}

// Erased EEPROM reads FFh: a byte of the image going 00h -> FFh is caught
// (a sum modulo 255 could not tell), and the older slot takes over.
TEST_F(Storage, AByteGoneToFFhFallsBackToTheOlderSet) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);  // slot 0: 1017h = 250
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);  // slot 1: 1017h = 300
  size_t at = 0;
  const size_t len = payload_bytes(od(), 0x1017, 0, &at);
  const size_t slot1 = kSlotBytes;
  ASSERT_GT(len, 0u);
  ASSERT_EQ(ram.mem[slot1 + 6 + at + 1], 0x01);  // 300 = 012Ch
  size_t zero = slot1 + 6;
  while (ram.mem[zero] != 0x00) ++zero;
  ram.mem[zero] = 0xFF;
  h.nmt(0x81, kId);
  EXPECT_TRUE(io.node().params_loaded());
  EXPECT_EQ(h.read(0x1017, 0), 250u) << "the older set";
  EXPECT_EQ(io.node().storage_damage_count(), 1u);
}

// A slot whose CRC is right but a value is beyond its entry's limits (2101h:
// 1..250) is not loaded: defaults, reported by EMCY 5530h after the boot-up
// and 1001h bit 0, until a save succeeds.
TEST_F(Storage, AValueBeyondItsLimitsRefusesTheSetAndIsReported) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  size_t at = 0;
  const size_t len = payload_bytes(od(), 0x2101, 0, &at);
  ASSERT_EQ(ram.mem[6 + at], 42);
  ram.mem[6 + at] = 251;
  const uint16_t crc = slot_crc(&ram.mem[0], len);
  ram.mem[6 + len] = static_cast<uint8_t>(crc);
  ram.mem[7 + len] = static_cast<uint8_t>(crc >> 8);
  bus.frames.clear();
  h.nmt(0x81, kId);
  expect_defaults();
  EXPECT_FALSE(io.node().params_loaded());
  EXPECT_EQ(io.node().storage_damage_count(), 1u);
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({"<703> 00", "<083> 30 55 01 00 00 00 00 00"})) << "boot-up, then EMCY 5530h";
  EXPECT_EQ(h.read(0x1001, 0), 0x01u);
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  h.advance_us(1000);
  EXPECT_EQ(h.take(), Frames({"<083> 00 00 00 00 00 00 00 00"})) << "error reset after a good save";
  EXPECT_EQ(h.read(0x1001, 0), 0x00u);
}

// Never saved (erased EEPROM, no file): defaults, nothing reported.
TEST_F(Storage, NothingSavedIsNoDamage) {
  h.nmt(0x81, kId);
  EXPECT_FALSE(io.node().params_loaded());
  EXPECT_EQ(io.node().storage_damage_count(), 0u);
  EXPECT_EQ(h.read(0x1001, 0), 0x00u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
