#include "timing/utilisation.h"

namespace mb2co {
namespace timing {
namespace {

void add_fixed(Fixed64& acc, uint64_t whole, uint64_t frac) {
  const uint64_t sum = acc.frac + frac;
  acc.whole += whole + (sum < frac ? 1u : 0u);
  acc.frac = sum;
}

}  // namespace

// Binary long division, one quotient bit per step: portable (no 128-bit type
// on the AVR), 64 steps.
uint64_t fraction_q64(uint64_t num, uint64_t den, bool* exact) {
  uint64_t rem = num;
  uint64_t quotient = 0;
  for (int i = 0; i < 64; ++i) {
    const bool carry = (rem >> 63) != 0;
    rem <<= 1;
    quotient <<= 1;
    if (carry || rem >= den) {
      rem -= den;  // wraps correctly when carry: the true value is < 2·den
      quotient |= 1u;
    }
  }
  *exact = rem == 0;
  return quotient;
}

void Utilisation::add(uint64_t c, uint64_t t) {
  const uint64_t whole = c / t;
  bool exact = true;
  const uint64_t frac = fraction_q64(c % t, t, &exact);
  add_fixed(lo_, whole, frac);
  if (exact) {
    add_fixed(hi_, whole, frac);
  } else if (frac == ~uint64_t{0}) {
    add_fixed(hi_, whole + 1u, 0u);
  } else {
    add_fixed(hi_, whole, frac + 1u);
  }
}

}  // namespace timing
}  // namespace mb2co
