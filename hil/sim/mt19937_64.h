// MT19937-64 as the C++ standard specifies std::mt19937_64 (the same stream
// for the same seed, word for word; tests/sim/test_rng.cpp compares them),
// written for the simulator's hot path: every idle firmware pass draws its
// jitter from it. Two differences from libstdc++'s engine, none in the
// numbers: the twist picks the matrix term without a branch (libstdc++'s
// `(y & 1) ? a : 0` is a branch taken at random, half of them mispredicted),
// and a draw is inline (the outputs of a state are tempered together when
// it is made).
#pragma once
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__)
#define MB2CO_SIM_TWIST_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define MB2CO_SIM_TWIST_CLONES
#endif

namespace mb2co {
namespace sim {

class Mt19937x64 {
 public:
  explicit Mt19937x64(uint64_t seed) {
    x_[0] = seed;
    for (size_t i = 1; i < kN; ++i) x_[i] = kInitMultiplier * (x_[i - 1] ^ (x_[i - 1] >> 62)) + i;
    p_ = kN;  // the first draw twists, as the standard's engine does
  }

  uint64_t operator()() {
    if (p_ >= kN) twist();
    return out_[p_++];
  }

 private:
  static constexpr size_t kN = 312;
  static constexpr size_t kM = 156;
  static constexpr uint64_t kMatrix = 0xB5026F5AA96619E9ull;
  static constexpr uint64_t kUpper = ~uint64_t{0} << 31;
  static constexpr uint64_t kLower = ~kUpper;
  static constexpr uint64_t kInitMultiplier = 6364136223846793005ull;

  /// One word of the recurrence: x_[k] from x_[k], x_[k1] and x_[km].
  static uint64_t next_word(uint64_t xk, uint64_t xk1, uint64_t xkm) {
    const uint64_t y = (xk & kUpper) | (xk1 & kLower);
    return xkm ^ (y >> 1) ^ ((uint64_t{0} - (y & 1)) & kMatrix);
  }
  static uint64_t temper(uint64_t z) {
    z ^= (z >> 29) & 0x5555555555555555ull;
    z ^= (z << 17) & 0x71D67FFFEDA60000ull;
    z ^= (z << 37) & 0xFFF7EEE000000000ull;
    return z ^ (z >> 43);
  }
  /// The next kN words of the state, and their outputs: tempered here, in
  /// a loop without dependencies between words, not on the draw's path.
  /// Built twice where the compiler can (GCC on x86-64): for AVX2 (four
  /// words a step) and for the baseline (two), picked once when the program
  /// loads (an ifunc on the CPU's features); integer steps only, so both give
  /// the same words (tests/sim/test_rng.cpp).
  MB2CO_SIM_TWIST_CLONES __attribute__((noinline)) void twist() {
    // Three loops of 156, 156 and 312 words (even: vectorised by pairs
    // without a remainder); x_[kN] is x_[0] as the first loop made it, so
    // that the last word's successor needs no loop of its own.
    size_t k = 0;
    for (; k < kN - kM; ++k) x_[k] = next_word(x_[k], x_[k + 1], x_[k + kM]);
    x_[kN] = x_[0];
    for (; k < kN; ++k) x_[k] = next_word(x_[k], x_[k + 1], x_[k + kM - kN]);
    for (k = 0; k < kN; ++k) out_[k] = temper(x_[k]);
    p_ = 0;
  }

  uint64_t x_[kN + 1];  ///< the state; x_[kN] is used by twist() alone
  uint64_t out_[kN];    ///< the draws of this state, in order (from x_[p_] on: not yet drawn)
  size_t p_;
};

}  // namespace sim
}  // namespace mb2co
