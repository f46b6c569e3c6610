// Random message sets for property tests (deterministic per seed).
#pragma once
#include <random>
#include <vector>

#include "timing/rta.h"

namespace mb2co {
namespace timing {

/// n messages with C in [c_min, c_min + c_span), T in [t_min, t_min + t_span),
/// D = T, and on every fourth message on average a jitter below j_span.
inline std::vector<RtaMessage> random_set(std::mt19937& rng, size_t n, uint64_t c_min, uint64_t c_span,
                                          uint64_t t_min, uint64_t t_span, uint64_t j_span) {
  std::vector<RtaMessage> set(n);
  for (auto& m : set) {
    m.c = c_min + rng() % c_span;
    m.t = t_min + rng() % t_span;
    m.d = m.t;
    m.j = rng() % 4 == 0 ? rng() % j_span : 0;
  }
  return set;
}

}  // namespace timing
}  // namespace mb2co
