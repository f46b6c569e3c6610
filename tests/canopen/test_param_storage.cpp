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
  ParamStorage api() { return ParamStorage{&RamStorage::read, &RamStorage::write, this}; }
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

TEST_F(Storage, CapabilityReadsOne) { EXPECT_EQ(h.read(0x1010, 1), 1u); }

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
  ASSERT_EQ(h.write_u16(0x1017, 0, 300), 0u);   // not saved
  ASSERT_EQ(h.write_u16(0x2101, 0, 77), 0u);    // not saved
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

// The stored image: magic "BM", payload length, payload, and a Fletcher-16
// (sums modulo 255) over header and payload, recomputed here independently.
TEST_F(Storage, TheImageCarriesAFletcher16OfHeaderAndPayload) {
  configure();
  ASSERT_EQ(h.write_u32(0x1010, 1, kSaveSignature), 0u);
  EXPECT_EQ(ram.mem[0], 0x42);
  EXPECT_EQ(ram.mem[1], 0x4D);
  const size_t len = ram.mem[2] | (ram.mem[3] << 8);
  ASSERT_GT(len, 16u);
  ASSERT_LT(len + 6, ram.mem.size());
  unsigned a = 0, b = 0;
  for (size_t i = 0; i < 4 + len; ++i) {
    a = (a + ram.mem[i]) % 255;
    b = (b + a) % 255;
  }
  EXPECT_EQ(ram.mem[4 + len], a);
  EXPECT_EQ(ram.mem[5 + len], b);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
