// Storing parameters (1010h "save", 1011h "load" = restore defaults) through
// a RAM-backed ParamStorage, and what survives which reset.
#include <gtest/gtest.h>

#include "ram_storage.h"
#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

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
  /// "save": the answer (0: accepted), then the passes until the save ends.
  uint32_t save() {
    const uint32_t answer = h.write_u32(0x1010, 1, kSaveSignature);
    finish_save();
    return answer;
  }
  void finish_save() {
    for (int pass = 0; pass < 100000 && io.node().saving(); ++pass) h.advance_us(100);
    EXPECT_FALSE(io.node().saving());
  }
  bool storage_error() { return io.node().emcy().active(0x5530); }
  RamStorage ram;
  ParamStorage api = ram.api();
};

TEST_F(Storage, CapabilityReadsOne) {
  EXPECT_EQ(h.read(0x1010, 1), 1u);
}

TEST_F(Storage, SavedParametersSurviveResetNode) {
  configure();
  EXPECT_EQ(save(), 0u);
  EXPECT_EQ(h.read(0x1010, 1), 1u) << "the signature is not stored";
  h.nmt(0x81, kId);
  EXPECT_EQ(h.take(), Frames({"<703> 00"}));
  expect_configured();
  EXPECT_TRUE(io.node().params_loaded());
}

TEST_F(Storage, ResetCommunicationReloadsOnlyTheCommunicationArea) {
  configure();
  ASSERT_EQ(save(), 0u);
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);  // not saved
  ASSERT_EQ(h.write_u16(0x2101, 0, 77), 0u);   // not saved
  h.nmt(0x82, kId);
  EXPECT_EQ(h.read(0x1017, 0), 250u) << "communication area: saved value";
  EXPECT_EQ(h.read(0x2101, 0), 77u) << "application area untouched by reset communication";
}

TEST_F(Storage, RestoreDefaultsTakesEffectAtTheNextReset) {
  configure();
  ASSERT_EQ(save(), 0u);
  ASSERT_EQ(h.write_u32(0x1011, 1, kLoadSignature), 0u);
  expect_configured();  // nothing changes until the reset
  h.nmt(0x81, kId);
  expect_defaults();
  EXPECT_FALSE(io.node().params_loaded());
}

// The answer leaves before the save is done; a storage failing on the way
// is reported as EMCY 5530h (1001h bit 0), and nothing of the set counts.
TEST_F(Storage, AnInterruptedSaveLeavesDefaultsAndIsReported) {
  configure();
  ram.writes_left = 3;  // dies in the middle of the payload
  EXPECT_EQ(save(), 0u) << "answered at once";
  expect_configured();
  EXPECT_TRUE(storage_error());
  EXPECT_EQ(h.read(0x1001, 0), 0x01u);
  ram.writes_left = -1;
  h.nmt(0x81, kId);
  expect_defaults();
}

TEST_F(Storage, ACorruptedImageIsIgnored) {
  configure();
  ASSERT_EQ(save(), 0u);
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
  ASSERT_EQ(save(), 0u);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1003, 0), 0u);
}

// CRC-16/MODBUS bit by bit (poly A001h reflected, init FFFFh), written here
// independently of shared/crc/crc16.cpp.
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
  for (unsigned n = 1; n <= 3; ++n) {
    ASSERT_EQ(save(), 0u);
    const uint8_t* s = &ram.mem[((n - 1) % 2) * kSlotBytes];
    EXPECT_EQ(s[0], 0x43);
    EXPECT_EQ(s[1], 0x32);
    EXPECT_EQ(s[2] | (s[3] << 8), static_cast<int>(n)) << "sequence number";
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
  ASSERT_EQ(save(), 0u);  // set A: 1017h = 250
  ASSERT_EQ(save(), 0u);  // again: both slots hold A
  const RamStorage with_a = ram;
  int cut = 0;
  for (;; ++cut) {
    ram = with_a;
    ASSERT_EQ(h.write_u16(0x1017, 0, 500), 0u);  // set B
    ram.writes_left = cut;
    ASSERT_EQ(save(), 0u);
    const bool saved = !storage_error();
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
  ASSERT_EQ(save(), 0u);  // slot 0: 1017h = 250
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);
  ASSERT_EQ(save(), 0u);  // slot 1: 1017h = 300
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
  ASSERT_EQ(save(), 0u);
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
  ASSERT_EQ(save(), 0u);
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

// A save on an EEPROM (3.3 ms per byte, ready() false meanwhile) runs over
// passes: answered at once, never a write while the medium is busy, the
// heartbeat keeps its period, 1010h/1 reads 0 until it is done, a second
// "save" or a "load" meanwhile is refused as busy (08000022h), and the new
// set is in force after it.
TEST_F(Storage, ASaveOnABusyEepromRunsOverPassesAndTheHeartbeatKeepsItsPeriod) {
  configure();
  ASSERT_EQ(h.write_u16(0x1017, 0, 100), 0u);
  ram.clock = &h.now;
  ram.busy_us = 3300;
  h.run_us(150000);
  bus.frames.clear();
  const uint32_t begin = h.now;
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u) << "answered at once";
  EXPECT_TRUE(io.node().saving());
  EXPECT_EQ(h.read(0x1010, 1), 0u) << "busy: poll until it reads 1";
  h.expect_abort({0x23, 0x10, 0x10, 0x01, 's', 'a', 'v', 'e'}, 0x1010, 1, kAbortDeviceState);
  h.expect_abort({0x23, 0x11, 0x10, 0x01, 'l', 'o', 'a', 'd'}, 0x1011, 1, kAbortDeviceState);
  std::vector<uint32_t> beats;
  while (io.node().saving() && h.now - begin < 10000000u) {
    uint32_t at = 0;
    ASSERT_TRUE(io.node().next_deadline(h.now, &at));
    ASSERT_LE(at - h.now, uint32_t{Node::kSavePollUs}) << "the save asks to be run again";
    h.advance_us(100);
    for (const CanFrame& f : h.take_frames()) {
      if (f.id == 0x700u + kId) beats.push_back(h.now);
    }
  }
  const uint32_t took = h.now - begin;
  const size_t bytes = 6 + payload_bytes(od()) + 2 + 2;  // header, payload, CRC, invalidation
  EXPECT_GE(took, (bytes - 1) * 3300u) << "one byte per 3.3 ms";
  EXPECT_LE(took, bytes * 3300u + bytes * 200u) << "no byte waits much longer than the medium";
  EXPECT_EQ(ram.early_writes, 0) << "never a write while the EEPROM programs a byte";
  ASSERT_GE(beats.size(), took / 100000u - 1) << "heartbeats during the save";
  for (size_t i = 1; i < beats.size(); ++i) {
    EXPECT_NEAR(static_cast<double>(beats[i] - beats[i - 1]), 100000.0, 200.0) << "heartbeat " << i;
  }
  EXPECT_FALSE(storage_error());
  EXPECT_EQ(h.read(0x1010, 1), 1u);
  ASSERT_EQ(h.write_u16(0x1017, 0, 0), 0u);
  h.nmt(0x81, kId);
  h.run_us(1000);
  EXPECT_TRUE(io.node().params_loaded());
  EXPECT_EQ(h.read(0x1017, 0), 100u);
  EXPECT_EQ(h.read(0x2101, 0), 42u);
}

// A reset asked for while a save runs (NMT here; the same for 2001h and a
// Modbus restart) waits until the save is done: "save, then reset" in one
// breath keeps what was saved.
TEST_F(Storage, AResetDuringASaveWaitsForItsEnd) {
  configure();
  ram.clock = &h.now;
  ram.busy_us = 3300;
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  h.nmt(0x81, kId);
  h.run_us(1000000);
  EXPECT_TRUE(io.node().saving());
  for (const std::string& f : h.take()) EXPECT_EQ(f, "<703> 7F") << "heartbeats, no boot-up while saving";
  finish_save();
  h.advance_us(100);
  const Frames after = h.take();
  ASSERT_FALSE(after.empty());
  EXPECT_EQ(after.back(), "<703> 00") << "then the reset";
  EXPECT_TRUE(io.node().params_loaded());
  expect_configured();
}

// An entry written while the save runs is saved whole, as it was when the
// save reached it or as written: never half of each.
TEST_F(Storage, AnEntryWrittenDuringTheSaveIsSavedWhole) {
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x80000183u), 0u);
  ram.clock = &h.now;
  ram.busy_us = 3300;
  size_t at = 0;
  payload_bytes(od(), 0x1800, 1, &at);
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  // Runs until the save has written the entry's first byte, not its last.
  while (io.node().saving() && ram.mem[6 + at] != 0x80)
    h.advance_us(100);  // 0x80000183 saved relative: 80 09 00 80
  ASSERT_TRUE(io.node().saving());
  ASSERT_EQ(h.write_u32(0x1800, 1, 0x40000183u), 0u);
  finish_save();
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1800, 1), 0x80000183u) << "the value the save reached";
}

// Issue 22 item 3: every single-bit flip in either slot of a two-slot image
// (slot 0: 1017h = 250, sequence 1; slot 1: 1017h = 300, sequence 2) is
// reported, and the set in force is the newest valid one. A flip in the
// newest slot's sequence number (bit 1: 2 -> 0, bit 15: 2 -> 8002h) makes it
// claim to be the older: only its CRC tells, and the older set in force is
// then a rollback the operator must be told of (EMCY 5530h, damage count).
TEST_F(Storage, EverySingleBitFlipLoadsTheNewestValidSetAndIsReported) {
  configure();
  ASSERT_EQ(save(), 0u);  // slot 0, sequence 1
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);
  ASSERT_EQ(save(), 0u);  // slot 1, sequence 2
  const size_t used = 6 + payload_bytes(od()) + 2;
  const RamStorage image = ram;
  unsigned flips = 0;
  for (size_t slot = 0; slot < 2; ++slot) {
    for (size_t byte = 0; byte < used; ++byte) {
      for (int bit = 0; bit < 8; ++bit) {
        ram = image;
        ram.mem[slot * kSlotBytes + byte] ^= static_cast<uint8_t>(1u << bit);
        const uint8_t reported_before = io.node().storage_damage_count();
        h.nmt(0x81, kId);
        const std::string where =
            "slot " + std::to_string(slot) + " byte " + std::to_string(byte) + " bit " + std::to_string(bit);
        ASSERT_TRUE(io.node().params_loaded()) << where;
        // The flipped slot is never the one in force: the other is valid.
        EXPECT_EQ(h.read(0x1017, 0), slot == 0 ? 300u : 250u) << where;
        // (the count saturates at 255; the EMCY is raised at every reset)
        if (reported_before != 0xFF) {
          EXPECT_EQ(io.node().storage_damage_count(), reported_before + 1u) << where << ": not counted";
        }
        EXPECT_TRUE(storage_error()) << where << ": no EMCY 5530h";
        ++flips;
      }
    }
  }
  EXPECT_EQ(flips, 2 * used * 8);
  ram = image;
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1017, 0), 300u) << "the image unflipped: the newest set";
  EXPECT_FALSE(storage_error()) << "and nothing to report";
}

/// Sets slot `slot`'s sequence number to `seq` with its CRC made right again.
void set_sequence(RamStorage& ram, size_t slot, uint16_t seq, size_t len) {
  uint8_t* s = &ram.mem[slot * kSlotBytes];
  s[2] = static_cast<uint8_t>(seq);
  s[3] = static_cast<uint8_t>(seq >> 8);
  const uint16_t crc = slot_crc(s, len);
  s[6 + len] = static_cast<uint8_t>(crc);
  s[7 + len] = static_cast<uint8_t>(crc >> 8);
}

// Sequence numbers wrap: FFFFh is followed by 0000h, which is the newer
// (their difference as int16, 1..32767 ahead), and saving goes on alternating.
TEST_F(Storage, TheSequenceNumberWrapsAroundAndTheNewerStaysInForce) {
  const size_t len = payload_bytes(od());
  configure();
  ASSERT_EQ(save(), 0u);  // slot 0
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);
  ASSERT_EQ(save(), 0u);  // slot 1
  set_sequence(ram, 0, 0xFFFE, len);
  set_sequence(ram, 1, 0xFFFF, len);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1017, 0), 300u) << "FFFFh is newer than FFFEh";
  EXPECT_EQ(io.node().storage_damage_count(), 0u);
  ASSERT_EQ(h.write_u16(0x1017, 0, 400), 0u);
  ASSERT_EQ(save(), 0u);  // into slot 0, sequence 0000h
  EXPECT_EQ(ram.mem[2] | (ram.mem[3] << 8), 0x0000);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1017, 0), 400u) << "0000h is newer than FFFFh";
  ASSERT_EQ(h.write_u16(0x1017, 0, 500), 0u);
  ASSERT_EQ(save(), 0u);  // into slot 1, sequence 0001h
  EXPECT_EQ(ram.mem[kSlotBytes + 2] | (ram.mem[kSlotBytes + 3] << 8), 0x0001);
  h.nmt(0x81, kId);
  EXPECT_EQ(h.read(0x1017, 0), 500u);
  EXPECT_EQ(io.node().storage_damage_count(), 0u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
