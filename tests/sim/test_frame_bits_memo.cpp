// The bus's remembered frame lengths are frame_bits_exact's answers for
// every frame, whatever came before it into the same slot: frames that
// differ in one data bit, in the dlc, in the id's width or RTR, and many
// frames more than the memo has slots.
#include <gtest/gtest.h>

#include <random>

#include "sim/frame_bits_memo.h"

namespace mb2co {
namespace sim {
namespace {

void expect_same(const timing::ExactFrameBits& got, const CanFrame& f) {
  const timing::ExactFrameBits want = timing::frame_bits_exact(f);
  EXPECT_EQ(got.total_bits, want.total_bits) << std::hex << f.id;
  EXPECT_EQ(got.stuff_bits, want.stuff_bits) << std::hex << f.id;
  EXPECT_EQ(got.crc15, want.crc15) << std::hex << f.id;
}

TEST(FrameBitsMemo, EveryFrameTakesItsOwnLengthWhateverCameBefore) {
  FrameBitsMemo memo;
  std::mt19937 rng(11);
  // Few ids and few values, so that frames repeat (hits) and differ in one
  // byte or bit from frames remembered (a stale slot would show).
  for (int i = 0; i < 20000; ++i) {
    CanFrame f = {};
    f.id = static_cast<uint32_t>(0x180u + rng() % 6u);
    f.flags = (rng() % 8u == 0) ? CanFrame::kExtended : 0;
    if (rng() % 16u == 0) f.flags = static_cast<uint8_t>(f.flags | CanFrame::kRtr);
    f.dlc = static_cast<uint8_t>(rng() % 10u);  // 9: more than 8 bytes named
    for (uint8_t& b : f.data) b = static_cast<uint8_t>(rng() % 3u == 0 ? rng() : 0x55);
    expect_same(memo.of(f), f);
    CanFrame g = f;  // the same frame with one data bit flipped
    g.data[rng() % 8u] ^= static_cast<uint8_t>(1u << (rng() % 8u));
    expect_same(memo.of(g), g);
    expect_same(memo.of(f), f);
  }
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
