// Seeded pseudo-random numbers for the simulator. std::mt19937_64 is fully
// specified by the C++ standard (Mt19937x64 is its stream, made faster); the
// distributions on top of it are our own (the standard library's are
// implementation-defined), so the same seed gives the same run with any
// compiler.
#pragma once
#include <stdint.h>

#include "sim/mt19937_64.h"

namespace mb2co {
namespace sim {

/// v % n and v / n for one n without a division instruction (a 64-bit
/// divide is tens of cycles, and every firmware pass draws with the same
/// bound): Granlund and Montgomery's multiply by a rounded-up reciprocal
/// ("Division by invariant integers using multiplication", 1994, fig. 4.1),
/// exact for every 64-bit v and every n >= 1.
class Divisor {
 public:
  explicit Divisor(uint64_t n = 1) : n_(n) {
    // l = ceil(log2 n): 2^(l-1) < n <= 2^l, so 2^l - n < n and m fits 64 bits.
    const unsigned l = n <= 1 ? 0u : 64u - static_cast<unsigned>(__builtin_clzll(n - 1));
    const uint64_t two_l_minus_n = (l == 64 ? 0 : uint64_t{1} << l) - n;  // mod 2^64: exact for l = 64
    m_ = static_cast<uint64_t>((static_cast<unsigned __int128>(two_l_minus_n) << 64) / n) + 1;
    sh1_ = l > 0 ? 1 : 0;
    sh2_ = l > 0 ? l - 1 : 0;
  }
  uint64_t n() const { return n_; }
  uint64_t quotient(uint64_t v) const {
    const uint64_t t = static_cast<uint64_t>((static_cast<unsigned __int128>(m_) * v) >> 64);
    return (t + ((v - t) >> sh1_)) >> sh2_;
  }
  uint64_t remainder(uint64_t v) const { return v - quotient(v) * n_; }

 private:
  uint64_t n_;
  uint64_t m_;
  unsigned sh1_;
  unsigned sh2_;
};

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
    if (n != bound_.n()) {  // a stream mostly draws with one bound: divide once
      bound_ = Divisor(n);
      limit_ = UINT64_MAX - bound_.remainder(UINT64_MAX);  // multiple of n
    }
    uint64_t v = g_();
    while (v >= limit_) v = g_();
    return bound_.remainder(v);
  }
  /// Uniform in [lo, hi] (inclusive; lo when hi <= lo).
  uint64_t range(uint64_t lo, uint64_t hi) { return hi <= lo ? lo : lo + below(hi - lo + 1); }
  /// True with probability ppm / 10^6.
  bool chance_ppm(uint32_t ppm) { return ppm != 0 && below(1000000) < ppm; }

 private:
  Mt19937x64 g_;
  Divisor bound_{1};             ///< the last bound drawn with
  uint64_t limit_ = UINT64_MAX;  ///< the largest multiple of bound_.n() in 64 bits (of 1 first)
};

}  // namespace sim
}  // namespace mb2co
