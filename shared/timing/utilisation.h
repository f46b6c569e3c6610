// Exact bounds on a utilisation Σ C_k/T_k without a common denominator (the
// LCM of 1,000 periods overflows anything): each term is added rounded down
// to `lo` and rounded up to `hi` in 64.64 fixed point, so lo ≤ U ≤ hi and
// hi - lo < n · 2^-64. Terms that divide exactly add no uncertainty.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace timing {

/// A 64.64 fixed-point value: whole + frac / 2^64.
struct Fixed64 {
  uint64_t whole = 0;
  uint64_t frac = 0;
};

class Utilisation {
 public:
  /// Adds c/t. Precondition: t > 0.
  void add(uint64_t c, uint64_t t);

  /// Certainly U < 1.
  bool below_one() const { return hi_.whole == 0; }

  /// Treat U as reaching 1: certainly U ≥ 1, or U lies within the rounding
  /// margin n · 2^-64 of 1 (a busy period would then be longer than the
  /// analysis horizon anyway).
  bool reaches_one() const { return !below_one(); }

  Fixed64 lower() const { return lo_; }
  Fixed64 upper() const { return hi_; }

 private:
  Fixed64 lo_;
  Fixed64 hi_;
};

/// floor(num · 2^64 / den) for num < den; `*exact` tells whether it divided.
uint64_t fraction_q64(uint64_t num, uint64_t den, bool* exact);

}  // namespace timing
}  // namespace mb2co
