// Seeded pseudo-random numbers for the simulator. std::mt19937_64 is fully
// specified by the C++ standard; the distributions on top of it are our own
// (the standard library's are implementation-defined), so the same seed gives
// the same run with any compiler.
#pragma once
#include <stdint.h>

#include <random>

namespace mb2co {
namespace sim {

/// SplitMix64 step: derives independent sub-seeds (one stream per station
/// and purpose) from the run's seed.
inline uint64_t mix_seed(uint64_t seed, uint64_t stream) {
  uint64_t z = seed + 0x9E3779B97F4A7C15ull * (stream + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  explicit Rng(uint64_t seed = 1) : g_(seed) {}
  uint64_t next() { return g_(); }
  /// Uniform in [0, n) without modulo bias; 0 when n == 0.
  uint64_t below(uint64_t n) {
    if (n == 0) return 0;
    if (n != limit_n_) {  // a stream mostly draws with one bound: divide once
      limit_n_ = n;
      limit_ = UINT64_MAX - UINT64_MAX % n;  // multiple of n
    }
    uint64_t v = g_();
    while (v >= limit_) v = g_();
    return v % n;
  }
  /// Uniform in [lo, hi] (inclusive; lo when hi <= lo).
  uint64_t range(uint64_t lo, uint64_t hi) { return hi <= lo ? lo : lo + below(hi - lo + 1); }
  /// True with probability ppm / 10^6.
  bool chance_ppm(uint32_t ppm) { return ppm != 0 && below(1000000) < ppm; }

 private:
  std::mt19937_64 g_;
  uint64_t limit_n_ = 0;  ///< bound that limit_ belongs to (0: none yet)
  uint64_t limit_ = 0;
};

}  // namespace sim
}  // namespace mb2co
