#include "canopen/param_storage.h"

namespace mb2co {
namespace canopen {

// Image: magic (2) | payload length (2) | payload | Fletcher-16 of header+payload (2).
static const uint16_t kMagic = 0x4D42;  // "BM"
static const uint16_t kHeader = 4;

bool param_is_saved(const OdEntry& e) {
  if (!(e.attr & kAttrRam) || !(e.attr & kAttrWrite)) return false;
  return e.hook != kHookStore && e.index != 0x1003;
}

namespace {
struct Fletcher {
  uint16_t a = 0, b = 0;
  void add(const uint8_t* p, uint16_t n) {
    // a, b < 255 before each step, so one subtraction is the modulo (no
    // division on the AVR: -56 B).
    for (uint16_t i = 0; i < n; ++i) {
      a = static_cast<uint16_t>(a + p[i]);
      if (a >= 255) a = static_cast<uint16_t>(a - 255);
      b = static_cast<uint16_t>(b + a);
      if (b >= 255) b = static_cast<uint16_t>(b - 255);
    }
  }
  uint16_t value() const { return static_cast<uint16_t>((b << 8) | a); }
};

// Bytes of row `r` in the image: its capacity when "save" keeps it, else 0.
uint16_t saved_bytes(const ObjectDictionary& od, uint16_t r) {
  return param_is_saved(od.entry(r)) ? od.capacity_of(r) : 0;
}

uint16_t payload_length(const ObjectDictionary& od) {
  uint16_t n = 0;
  for (uint16_t r = 0; r < od.row_count(); ++r) n = static_cast<uint16_t>(n + saved_bytes(od, r));
  return n;
}
}  // namespace

bool params_erase(const ParamStorage& st) {
  const uint8_t zero[2] = {0, 0};
  return st.write(st.ctx, 0, zero, 2);
}

bool params_save(const ObjectDictionary& od, const ParamStorage& st) {
  // Invalidate first, write the payload, then the checksum and the header
  // last: a reset in between leaves an image that does not verify.
  if (!params_erase(st)) return false;
  const uint16_t len = payload_length(od);
  uint8_t header[kHeader];
  put_le16(header, kMagic);
  put_le16(header + 2, len);
  Fletcher sum;
  sum.add(header, kHeader);
  uint16_t at = kHeader;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint16_t n = saved_bytes(od, r);
    if (n == 0) continue;
    const uint8_t* p = od.ram(r);
    if (!st.write(st.ctx, at, p, n)) return false;
    sum.add(p, n);
    at = static_cast<uint16_t>(at + n);
  }
  uint8_t check[2];
  put_le16(check, sum.value());
  if (!st.write(st.ctx, at, check, 2)) return false;
  return st.write(st.ctx, 0, header, kHeader);
}

bool params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index,
                 uint16_t to_index) {
  uint8_t header[kHeader];
  if (!st.read(st.ctx, 0, header, kHeader)) return false;
  const uint16_t len = payload_length(od);
  if (le16(header) != kMagic || le16(header + 2) != len) return false;
  // Pass 1 verifies the checksum in small chunks (no image-sized buffer).
  Fletcher sum;
  sum.add(header, kHeader);
  uint8_t chunk[8];
  for (uint16_t done = 0; done < len;) {
    const uint16_t n = static_cast<uint16_t>(len - done < 8 ? len - done : 8);
    if (!st.read(st.ctx, static_cast<uint16_t>(kHeader + done), chunk, n)) return false;
    sum.add(chunk, n);
    done = static_cast<uint16_t>(done + n);
  }
  uint8_t check[2];
  if (!st.read(st.ctx, static_cast<uint16_t>(kHeader + len), check, 2)) return false;
  if (le16(check) != sum.value()) return false;
  // Pass 2 copies straight into the value block.
  uint16_t at = kHeader;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    const uint16_t n = saved_bytes(od, r);
    if (n == 0) continue;
    const uint16_t index = od.index_of(r);
    if (index >= from_index && index <= to_index && !st.read(st.ctx, at, od.ram(r), n)) {
      return false;
    }
    at = static_cast<uint16_t>(at + n);
  }
  return true;
}

}  // namespace canopen
}  // namespace mb2co
