// Values as the bus carries them (little-endian bytes) and the IEEE 754 bits
// of reals, for tests that compare frames, SDO data and registers with them.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <cstring>
#include <vector>

namespace mb2co {
namespace test {

/// The low `n` bytes of `v`, least significant first.
inline std::vector<uint8_t> le_bytes(uint64_t v, size_t n) {
  std::vector<uint8_t> b(n);
  for (size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(v >> (8 * i));
  return b;
}
inline uint32_t bits_of(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}
inline uint64_t bits_of(double d) {
  uint64_t u;
  std::memcpy(&u, &d, 8);
  return u;
}

}  // namespace test
}  // namespace mb2co
