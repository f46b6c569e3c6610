// Deterministic randomized property test: 200,000 random frames (lengths
// 0..8, RTR, half of the SDO requests aimed at real OD entries) on the node's
// COB-IDs, random time steps across the 2^32 µs wrap, interleaved with valid
// SDO transactions whose results are checked. Invariants, checked on every
// frame the node sends and at the end:
//   * it only sends on its own ids: 580h/700h + id, the current EMCY COB-ID,
//     the current SYNC COB-ID while producing, the current valid TPDO COB-IDs;
//   * SDO responses are 8 bytes with a defined command specifier, and aborts
//     carry only CiA 301 codes;
//   * const entries never change; the node still answers valid SDO requests.
#include <gtest/gtest.h>

#include <random>

#include "fuzz/node_invariants.h"
#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using namespace canopen;

const uint8_t kId = 3;

/// A sink that checks every frame against the OD as it is at that moment.
class CheckingBus {
 public:
  CanSink sink() { return CanSink{&CheckingBus::send, this}; }
  ionode::IoNode* node = nullptr;
  FrameLog log;  ///< SDO responses, for the harness
  uint64_t sent = 0;
  uint64_t aborts = 0;
  uint64_t sdo_ok = 0;
  std::vector<std::string> violations;

 private:
  static bool send(void* ctx, const CanFrame& f) {
    CheckingBus& b = *static_cast<CheckingBus*>(ctx);
    ++b.sent;
    const std::string why = frame_violation(*b.node, f);
    if (!why.empty() && b.violations.size() < 20) b.violations.push_back(why + ": " + to_string(f));
    if (f.id == 0x580u + kId) {
      ++(f.data[0] == 0x80 ? b.aborts : b.sdo_ok);
      b.log.frames.push_back(f);
    }
    return true;
  }
};

class Rng {
 public:
  explicit Rng(uint32_t seed) : mt_(seed) {}
  uint32_t next() { return static_cast<uint32_t>(mt_()); }
  uint32_t below(uint32_t n) { return next() % n; }
  uint8_t byte() { return static_cast<uint8_t>(next()); }
  bool chance(uint32_t percent) { return below(100) < percent; }

 private:
  std::mt19937 mt_;  // the engine's sequence is fixed by the standard
};

TEST(RandomFrames, TwoHundredThousandFramesKeepTheInvariants) {
  CheckingBus bus;
  ionode::IoNode io(bus.sink());
  bus.node = &io;
  Harness h(io.node(), bus.log);
  h.now = 0xFFFFFFFFu - 600000000u;  // the run crosses the wrap after ~10 minutes
  io.start(kId, h.now);

  ObjectDictionary& od = io.od();
  std::vector<uint16_t> indices;
  std::vector<std::pair<uint16_t, Bytes>> consts;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const OdEntry e = od.entry(r);
    // The node's own id (2001h) stays 3: the frames below are addressed to it
    // (test_ionode_config.cpp changes it on purpose).
    if (e.index == 0x2001) continue;
    if (indices.empty() || indices.back() != e.index) indices.push_back(e.index);
    if (e.attr & kAttrConst) {
      uint8_t buf[64];
      consts.emplace_back(r, Bytes(buf, buf + od.copy_out(r, buf, sizeof buf)));
    }
  }
  const uint32_t ids[] = {0x000, 0x080, 0x603, 0x603, 0x603, 0x603, 0x703, 0x183, 0x283,
                          0x383, 0x483, 0x203, 0x303, 0x403, 0x503, 0x705, 0x583, 0x083};
  const uint8_t cmds[] = {0x20, 0x21, 0x22, 0x23, 0x27, 0x2B, 0x2F, 0x40, 0x60,
                          0x70, 0x00, 0x10, 0x01, 0x11, 0x80, 0xA0, 0xC0, 0xE0};

  Rng rng(20240601u);
  uint64_t transactions = 0;
  int wraps = 0;
  for (int i = 0; i < 200000; ++i) {
    CanFrame f = {};
    f.id = rng.chance(3) ? rng.below(0x800) : ids[rng.below(sizeof ids / sizeof ids[0])];
    f.dlc = static_cast<uint8_t>(rng.below(9));
    if (f.id == 0x603 && rng.chance(80)) f.dlc = 8;
    if (f.id == 0x000 && rng.chance(50)) f.dlc = 2;
    if (rng.chance(8)) f.flags = CanFrame::kRtr;
    if (rng.chance(1)) f.flags = static_cast<uint8_t>(f.flags | CanFrame::kExtended);
    for (uint8_t& b : f.data) b = rng.byte();
    if (f.id == 0x603 && rng.chance(60)) {
      f.data[0] = cmds[rng.below(sizeof cmds)];
      const uint16_t index = indices[rng.below(static_cast<uint32_t>(indices.size()))];
      f.data[1] = static_cast<uint8_t>(index);
      f.data[2] = static_cast<uint8_t>(index >> 8);
      f.data[3] = static_cast<uint8_t>(rng.chance(60) ? rng.below(3) : rng.below(10));
      if (rng.chance(50)) {  // plausible small values
        f.data[5] = f.data[6] = 0;
        f.data[7] = rng.chance(70) ? 0 : 0x80;
      }
    }
    if (f.id == 0x000 && f.dlc == 2) f.data[1] = rng.chance(50) ? kId : static_cast<uint8_t>(rng.below(4));
    if (f.id == 0x000 && rng.chance(80)) f.data[0] = rng.chance(50) ? 0x01 : 0x80;  // fewer resets
    const uint32_t before = h.now;
    h.now += rng.chance(1) ? rng.below(3000000) : rng.below(20000);
    if (h.now < before) ++wraps;
    h.rx(f);
    bus.log.frames.clear();

    if (i % 997 == 0) {  // a valid transaction: pre-operational, write, read back
      ++transactions;
      h.nmt(0x80, kId);
      bus.log.frames.clear();
      const uint16_t debounce = static_cast<uint16_t>(1 + rng.below(250));
      ASSERT_EQ(h.write_u16(0x2101, 0, debounce), 0u) << "at frame " << i;
      ASSERT_EQ(h.read(0x2101, 0), debounce);
      std::string label;
      const uint32_t len = rng.below(25);
      for (uint32_t k = 0; k < len; ++k) label.push_back(static_cast<char>('A' + rng.below(26)));
      ASSERT_EQ(h.download_segmented(0x2000, 0, bytes_of(label), rng.chance(50)), 0u);
      ASSERT_EQ(h.read_string(0x2000, 0), label);
      ASSERT_EQ(h.read(0x1018, 2), 0x401u);
      bus.log.frames.clear();
    }
  }

  EXPECT_TRUE(bus.violations.empty()) << ::testing::PrintToString(bus.violations);
  for (const auto& c : consts) {
    uint8_t buf[64];
    const Bytes now(buf, buf + od.copy_out(c.first, buf, sizeof buf));
    EXPECT_EQ(now, c.second) << "const row " << c.first;
  }
  h.nmt(0x80, kId);
  bus.log.frames.clear();
  EXPECT_EQ(h.read(0x1000, 0), 0x00030191u);
  EXPECT_EQ(h.read_string(0x1008, 0), "mb2co I/O node");
  EXPECT_EQ(h.read(0x1018, 3), 1u);
  // The run was not vacuous.
  EXPECT_GT(transactions, 150u);
  ::testing::Test::RecordProperty("frames_sent", std::to_string(bus.sent));
  ::testing::Test::RecordProperty("sdo_confirmations", std::to_string(bus.sdo_ok));
  ::testing::Test::RecordProperty("sdo_aborts", std::to_string(bus.aborts));
  EXPECT_GT(bus.sdo_ok, 2000u);
  EXPECT_GT(bus.aborts, 10000u);
  EXPECT_GE(wraps, 1) << "the clock wrapped during the run";
}

}  // namespace
}  // namespace test
}  // namespace mb2co
