// The seed images of the param_image fuzz target (tests/fuzz/corpus/
// param_image) are of today's storage layout: each loads as the set it was
// saved with. A seed of an older layout only ever reaches the "damaged"
// branch; a random mutation cannot forge a CRC, so the fuzzer would never
// see a loaded set and its value checks (that was the case from the two-slot
// layout until 2026-11-26). Images saved by mb2co-node over Modbus (mbpoll:
// FC 16 of 6576h 6173h, "save", to HR 11-12).
#include <gtest/gtest.h>
#include <stdint.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../canopen/ram_storage.h"
#include "canopen/param_storage.h"
#include "gateway/gateway.h"

namespace mb2co {
namespace {

bool no_frame(void*, const CanFrame&) {
  return true;
}
bool no_bytes(void*, const uint8_t*, uint16_t) {
  return true;
}

struct Started {
  uint8_t node_id;
  uint16_t debounce_ms;  ///< 2000h/6 = HR 7
  uint8_t damage_count;  ///< 2003h/0
};

Started start_from(const std::string& seed) {
  test::RamStorage eeprom;  // the Uno's 1 KiB; beyond the file: erased (FFh)
  std::ifstream in(std::string(MB2CO_FUZZ_CORPUS) + "/param_image/" + seed, std::ios::binary);
  EXPECT_TRUE(in.good()) << seed;
  const std::vector<uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  EXPECT_LE(file.size(), eeprom.mem.size()) << seed;
  std::copy(file.begin(), file.begin() + static_cast<long>(std::min(file.size(), eeprom.mem.size())),
            eeprom.mem.begin());
  const std::vector<uint8_t> before = eeprom.mem;
  const canopen::ParamStorage storage = eeprom.api();
  gateway::Gateway g(gateway::GatewayPorts{CanSink{&no_frame, nullptr}, modbus::ByteSink{&no_bytes, nullptr},
                                           &storage, 115200});
  g.start(1000);
  g.process(1000, 0);  // the pass after a start publishes 2003h
  Started s{};
  uint8_t b[2] = {0, 0};
  uint16_t n = 0;
  EXPECT_EQ(g.od().read(0x2000, 1, b, 1, &n), canopen::kSdoOk);
  s.node_id = b[0];
  EXPECT_EQ(g.od().read(0x2000, 6, b, 2, &n), canopen::kSdoOk);
  s.debounce_ms = static_cast<uint16_t>(b[0] | b[1] << 8);
  EXPECT_EQ(g.od().read(0x2003, 0, b, 1, &n), canopen::kSdoOk);
  s.damage_count = b[0];
  EXPECT_EQ(eeprom.mem, before) << seed << ": a start never writes";
  return s;
}

TEST(FuzzSeedImages, EachLoadsAsTheSetItWasSavedWith) {
  const Started defaults = start_from("saved-defaults");
  EXPECT_EQ(defaults.node_id, 1);
  EXPECT_EQ(defaults.damage_count, 0);

  const Started one = start_from("saved-hr7-33-node-9");
  EXPECT_EQ(one.node_id, 9);
  EXPECT_EQ(one.debounce_ms, 33);
  EXPECT_EQ(one.damage_count, 0);

  const Started twice = start_from("saved-twice-hr7-40");
  EXPECT_EQ(twice.node_id, 9);
  EXPECT_EQ(twice.debounce_ms, 40) << "the newer slot is in force";
  EXPECT_EQ(twice.damage_count, 0);

  const Started flipped = start_from("saved-twice-newer-bit-flipped");
  EXPECT_EQ(flipped.node_id, 9);
  EXPECT_EQ(flipped.debounce_ms, 33) << "the newer slot is damaged: the older set";
  EXPECT_EQ(flipped.damage_count, 1);
}

}  // namespace
}  // namespace mb2co
