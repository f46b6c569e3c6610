#include "canopen/od.h"

#include <string.h>

namespace mb2co {
namespace canopen {

// Value bytes are kept in bus order (little-endian). Both targets are
// little-endian, so the generated value structs can be read directly too.
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "mb2co keeps OD values in little-endian order and reads them natively"
#endif

ObjectDictionary::ObjectDictionary(const OdDefinition& def, uint8_t* values)
    : def_(def), values_(values), hook_(nullptr), hook_ctx_(nullptr), node_id_(0) {
  for (uint8_t t = 0; t <= kUnsigned32; ++t) {
    const uint16_t r = t == 0 ? kNoRow : find(t, 0);
    type_bits_[t] = r == kNoRow ? 0 : static_cast<uint8_t>(flash_read(&def_.rows[r].def));
  }
}

uint16_t ObjectDictionary::find(uint16_t index, uint8_t sub) const {
  uint16_t lo = 0;
  uint16_t hi = def_.row_count;
  const uint32_t key = (static_cast<uint32_t>(index) << 8) | sub;
  while (lo < hi) {
    const uint16_t mid = static_cast<uint16_t>(lo + (hi - lo) / 2);
    const OdEntry* r = &def_.rows[mid];
    const uint32_t k = (static_cast<uint32_t>(flash_read(&r->index)) << 8) | flash_read(&r->sub);
    if (k == key) return mid;
    if (k < key) {
      lo = static_cast<uint16_t>(mid + 1);
    } else {
      hi = mid;
    }
  }
  return kNoRow;
}

uint16_t ObjectDictionary::first_row(uint16_t index) const {
  uint16_t lo = 0;
  uint16_t hi = def_.row_count;
  while (lo < hi) {  // lower bound of (index, 0)
    const uint16_t mid = static_cast<uint16_t>(lo + (hi - lo) / 2);
    if (flash_read(&def_.rows[mid].index) < index) {
      lo = static_cast<uint16_t>(mid + 1);
    } else {
      hi = mid;
    }
  }
  if (lo < def_.row_count && flash_read(&def_.rows[lo].index) == index) return lo;
  return kNoRow;
}

bool ObjectDictionary::has_index(uint16_t index) const { return first_row(index) != kNoRow; }

uint8_t ObjectDictionary::type_bits(uint8_t type) const {
  return type <= kUnsigned32 ? type_bits_[type] : 0;
}

uint16_t ObjectDictionary::capacity_of(uint16_t row) const {
  const OdEntry e = entry(row);
  if (e.attr & kAttrString) return static_cast<uint16_t>(e.def >> 16);
  return static_cast<uint16_t>((type_bits(e.type) + 7) / 8);
}

uint16_t ObjectDictionary::size_of(uint16_t row) const {
  const OdEntry e = entry(row);
  if (!(e.attr & kAttrString)) return static_cast<uint16_t>((type_bits(e.type) + 7) / 8);
  const uint16_t cap = static_cast<uint16_t>(e.def >> 16);
  uint16_t n = 0;
  if (e.attr & kAttrRam) {
    const uint8_t* p = values_ + e.loc;
    while (n < cap && p[n] != 0) ++n;
  } else {
    const char* p = def_.strings + (e.def & 0xFFFFu);
    while (n < cap && flash_byte(p + n) != 0) ++n;
  }
  return n;
}

uint32_t ObjectDictionary::default_of(const OdEntry& e) const {
  return (e.attr & kAttrNodeId) ? e.def + node_id_ : e.def;
}

uint32_t ObjectDictionary::get(uint16_t row) const {
  const OdEntry e = entry(row);
  if (!(e.attr & kAttrRam)) return default_of(e);
  const uint8_t* p = values_ + e.loc;
  switch (size_of(row)) {
    case 1:
      return p[0];
    case 2:
      return le16(p);
    case 4:
      return le32(p);
    default:
      return 0;
  }
}

bool ObjectDictionary::set(uint16_t row, uint32_t value) {
  const OdEntry e = entry(row);
  if (!(e.attr & kAttrRam) || (e.attr & kAttrString)) return false;
  uint8_t bytes[4];
  put_le32(bytes, value);
  const uint16_t n = size_of(row);
  uint8_t* p = values_ + e.loc;
  if (memcmp(p, bytes, n) == 0) return false;
  memcpy(p, bytes, n);
  return true;
}

uint8_t* ObjectDictionary::ram(uint16_t row) {
  const OdEntry e = entry(row);
  return (e.attr & kAttrRam) ? values_ + e.loc : nullptr;
}

const uint8_t* ObjectDictionary::ram(uint16_t row) const {
  const OdEntry e = entry(row);
  return (e.attr & kAttrRam) ? values_ + e.loc : nullptr;
}

uint16_t ObjectDictionary::copy_out(uint16_t row, uint8_t* buf, uint16_t cap) const {
  const OdEntry e = entry(row);
  uint16_t n = size_of(row);
  if (n > cap) n = cap;
  if (e.attr & kAttrRam) {
    memcpy(buf, values_ + e.loc, n);
  } else if (e.attr & kAttrString) {
    const char* p = def_.strings + (e.def & 0xFFFFu);
    for (uint16_t i = 0; i < n; ++i) buf[i] = flash_byte(p + i);
  } else {
    uint8_t bytes[4];
    put_le32(bytes, default_of(e));
    memcpy(buf, bytes, n > 4 ? 4 : n);
  }
  return n;
}

void ObjectDictionary::restore_defaults(uint16_t from_index, uint16_t to_index) {
  for (uint16_t r = 0; r < def_.row_count; ++r) {
    const OdEntry e = entry(r);
    if (e.index < from_index || e.index > to_index || !(e.attr & kAttrRam)) continue;
    if (e.attr & kAttrString) {
      const uint16_t cap = static_cast<uint16_t>(e.def >> 16);
      const char* src = def_.strings + (e.def & 0xFFFFu);
      uint8_t* dst = values_ + e.loc;
      uint16_t i = 0;
      for (; i < cap && flash_byte(src + i) != 0; ++i) dst[i] = flash_byte(src + i);
      for (; i < cap; ++i) dst[i] = 0;
    } else {
      uint8_t bytes[4];
      put_le32(bytes, default_of(e));
      memcpy(values_ + e.loc, bytes, size_of(r));
    }
  }
}

uint32_t ObjectDictionary::check_read(uint16_t index, uint8_t sub, uint16_t* row) const {
  const uint16_t r = find(index, sub);
  if (r == kNoRow) return has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  if (!(entry(r).attr & kAttrRead)) return kAbortWriteOnly;
  *row = r;
  return kSdoOk;
}

uint32_t ObjectDictionary::read(uint16_t index, uint8_t sub, uint8_t* buf, uint16_t cap,
                                uint16_t* len) const {
  uint16_t r = kNoRow;
  const uint32_t abort = check_read(index, sub, &r);
  if (abort != kSdoOk) return abort;
  if (size_of(r) > cap) return kAbortTooLong;
  *len = copy_out(r, buf, cap);
  return kSdoOk;
}

uint32_t ObjectDictionary::check_write(uint16_t index, uint8_t sub, uint16_t* row) const {
  const uint16_t r = find(index, sub);
  if (r == kNoRow) return has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  if (!(entry(r).attr & kAttrWrite)) return kAbortReadOnly;
  *row = r;
  return kSdoOk;
}

// Sign- or zero-extends a little-endian value of `len` bytes of type `type`.
static int64_t decode_number(uint8_t type, const uint8_t* data, uint16_t len) {
  uint32_t u = 0;
  for (uint16_t i = 0; i < len && i < 4; ++i) u |= static_cast<uint32_t>(data[i]) << (8 * i);
  const bool is_signed = type == kInteger8 || type == kInteger16 || type == kInteger32;
  if (is_signed && len > 0 && len < 4 && (data[len - 1] & 0x80)) {
    u |= ~((static_cast<uint32_t>(1) << (8 * len)) - 1);
  }
  return is_signed ? static_cast<int64_t>(static_cast<int32_t>(u)) : static_cast<int64_t>(u);
}

uint32_t ObjectDictionary::check_limits(const OdEntry& e, const uint8_t* data,
                                        uint16_t len) const {
  if (e.type == kBoolean && data[0] > 1) return kAbortInvalidValue;
  for (uint8_t i = 0; i < def_.limit_count; ++i) {
    const OdLimit lim = flash_read(&def_.limits[i]);
    if (lim.index != e.index || lim.sub != e.sub) continue;
    const int64_t v = decode_number(e.type, data, len);
    if (v < lim.min) return kAbortValueTooLow;
    if (v > lim.max) return kAbortValueTooHigh;
  }
  return kSdoOk;
}

void ObjectDictionary::store(const OdEntry& e, const uint8_t* data, uint16_t len) {
  uint8_t* p = values_ + e.loc;
  memcpy(p, data, len);
  if (e.attr & kAttrString) {
    const uint16_t cap = static_cast<uint16_t>(e.def >> 16);
    if (len < cap) memset(p + len, 0, cap - len);
  }
}

uint32_t ObjectDictionary::write(uint16_t index, uint8_t sub, const uint8_t* data, uint16_t len) {
  uint16_t r = kNoRow;
  uint32_t abort = check_write(index, sub, &r);
  if (abort != kSdoOk) return abort;
  const OdEntry e = entry(r);
  const uint16_t cap = capacity_of(r);
  if (len > cap) return kAbortTooLong;
  if (!(e.attr & kAttrString) && len < cap) return kAbortTooShort;
  if (!(e.attr & kAttrString)) {
    abort = check_limits(e, data, len);
    if (abort != kSdoOk) return abort;
  }
  if (e.hook != kHookNone && hook_ != nullptr) {
    abort = hook_(hook_ctx_, e.hook, index, sub, data, len);
    if (abort == kHookHandled) return kSdoOk;
    if (abort != kSdoOk) return abort;
  }
  store(e, data, len);
  return kSdoOk;
}

}  // namespace canopen
}  // namespace mb2co
