#include "canopen/od.h"

#include <string.h>

namespace mb2co {
namespace canopen {

// Value bytes are kept in bus order (little-endian). Both targets are
// little-endian, so the generated value structs can be read directly too.
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "mb2co keeps OD values in little-endian order and reads them natively"
#endif

// Per DataType code: bytes of a numeric value (low nibble; 0 for the
// byte-run types, sized by their capacity) and the OdTypeKind (high
// nibble). One flash byte per code, read on every value access.
#define MB2CO_OD_TYPE_INFO(t) \
  static_cast<uint8_t>((od_type_is_bytes(t) ? 0 : (od_type_bit_length(t) + 7) / 8) | (od_type_kind(t) << 4))
static const uint8_t kOdTypeInfo[kOdTypeCount] MB2CO_FLASH = {
    MB2CO_OD_TYPE_INFO(0x00), MB2CO_OD_TYPE_INFO(0x01), MB2CO_OD_TYPE_INFO(0x02), MB2CO_OD_TYPE_INFO(0x03),
    MB2CO_OD_TYPE_INFO(0x04), MB2CO_OD_TYPE_INFO(0x05), MB2CO_OD_TYPE_INFO(0x06), MB2CO_OD_TYPE_INFO(0x07),
    MB2CO_OD_TYPE_INFO(0x08), MB2CO_OD_TYPE_INFO(0x09), MB2CO_OD_TYPE_INFO(0x0A), MB2CO_OD_TYPE_INFO(0x0B),
    MB2CO_OD_TYPE_INFO(0x0C), MB2CO_OD_TYPE_INFO(0x0D), MB2CO_OD_TYPE_INFO(0x0E), MB2CO_OD_TYPE_INFO(0x0F),
    MB2CO_OD_TYPE_INFO(0x10), MB2CO_OD_TYPE_INFO(0x11), MB2CO_OD_TYPE_INFO(0x12), MB2CO_OD_TYPE_INFO(0x13),
    MB2CO_OD_TYPE_INFO(0x14), MB2CO_OD_TYPE_INFO(0x15), MB2CO_OD_TYPE_INFO(0x16), MB2CO_OD_TYPE_INFO(0x17),
    MB2CO_OD_TYPE_INFO(0x18), MB2CO_OD_TYPE_INFO(0x19), MB2CO_OD_TYPE_INFO(0x1A), MB2CO_OD_TYPE_INFO(0x1B),
    MB2CO_OD_TYPE_INFO(0x1C), MB2CO_OD_TYPE_INFO(0x1D), MB2CO_OD_TYPE_INFO(0x1E), MB2CO_OD_TYPE_INFO(0x1F)};
#undef MB2CO_OD_TYPE_INFO

ObjectDictionary::ObjectDictionary(const OdDefinition& def, uint8_t* values)
    : def_(def), values_(values), revision_(0), node_id_(0), owners_() {
#if MB2CO_CONFIG_OD_DIRECT_GET
  resolve_direct();
#endif
}

#if MB2CO_CONFIG_OD_DIRECT_GET
void ObjectDictionary::resolve_direct() {
  static const uint32_t kWidthMask[5] = {0, 0xFFu, 0xFFFFu, 0xFFFFFFu, 0xFFFFFFFFu};
  memset(found_, 0, sizeof found_);
  memset(direct_, 0, sizeof direct_);
  direct_rows_ = def_.row_count < kDirectRows ? def_.row_count : kDirectRows;
  for (uint16_t row = 0; row < direct_rows_; ++row) {
    const Place pl = place(row);
    Direct& d = direct_[row];
    d.index = static_cast<uint16_t>(flash_read(&pl.row->index) + pl.n);
    d.sub = flash_read(&pl.row->sub);
    d.attr = flash_read(&pl.row->attr);
    d.numeric = (d.attr & kAttrString) ? 0 : numeric_size(pl.row);
    if ((d.attr & (kAttrRam | kAttrString)) != kAttrRam || d.numeric == 0 || d.numeric > 4) continue;
    // A value in the block's last 3 bytes is decoded: its 4-byte load would
    // read past values_.
    const uint16_t offset = static_cast<uint16_t>(value_at(pl) - values_);
    if (offset + 4u > def_.values_size) continue;
    d.offset = offset;
    d.mask = kWidthMask[d.numeric];
  }
}

// Remembered answers first (found_): the search costs ~120 instructions, a
// hit ~10, and the hosts' hot paths (a PDO's mapped entries, a Modbus
// table's map) ask for the same few keys on every frame and request.
uint16_t ObjectDictionary::find(uint16_t index, uint8_t sub) const {
  const uint32_t key = ((static_cast<uint32_t>(index) << 8) | sub) + 1u;
  Found& f = found_[(key * 0x9E3779B1u) >> 24];  // Fibonacci hashing: the top 8 bits
  if (f.key != key) {
    f.row = search(index, sub);
    f.key = key;
  }
  return f.row;
}
#endif

uint8_t ObjectDictionary::row_type(const OdRow* e) {
  const uint8_t low = flash_read(reinterpret_cast<const uint8_t*>(e) + kOdEntryTypeHookOffset) & 0x0F;
  return (loc_word(e) & ~kOdLocMask) ? static_cast<uint8_t>(low | 0x10) : low;
}

uint8_t ObjectDictionary::numeric_size(const OdRow* e) const {
  return flash_read(&kOdTypeInfo[row_type(e)]) & 0x0F;
}

// Row numbers count every row of the sorted list: record_first rows below
// the records, then record_count rows of records (kind by kind, PDO by
// PDO), then the rest. def_.rows holds all but the records' rows. The
// short path (every row but the records') reads no flash: the bounds are
// in the definition.
ObjectDictionary::Place ObjectDictionary::place(uint16_t row) const {
  const uint16_t first = def_.record_first;
  const uint16_t count = def_.record_count;
  Place p = {nullptr, 0, 0};
  const uint16_t k = static_cast<uint16_t>(row - first);  // wraps below the records
  if (k >= count) {
    p.row = &def_.rows[row < first ? row : row - count];
    return p;
  }
  // OdRecordTable: OdRecords, count / kOdRecordsPerKind template rows, a
  // byte per record row naming its template row and n.
  const OdRecordRow* templates = reinterpret_cast<const OdRecordRow*>(def_.records + 1);
  const uint8_t named =
      flash_read(reinterpret_cast<const uint8_t*>(templates + count / kOdRecordsPerKind) + k);
  const OdRecordRow* t = templates + (named & kOdRecordTemplateMask);
  p.row = &t->row;
  p.n = static_cast<uint8_t>(named >> kOdRecordNumberShift);
  p.stride = flash_read(&t->stride);
  return p;
}

#if MB2CO_CONFIG_OD_DIRECT_GET
uint16_t ObjectDictionary::decoded_index(uint16_t row) const {
#else
uint16_t ObjectDictionary::index_of(uint16_t row) const {
#endif
  const Place p = place(row);
  return static_cast<uint16_t>(flash_read(&p.row->index) + p.n);
}

uint32_t ObjectDictionary::def_at(Place p) const {
  const uint8_t slot = flash_read(slot_at(p));
  if (slot & kOdLiteralDefaults) return static_cast<uint8_t>(slot & ~kOdLiteralDefaults);
  return flash_read(&def_.defaults[slot]);
}

OdEntry ObjectDictionary::entry(uint16_t row) const {
  const Place p = place(row);
  OdEntry out;
  flash_copy(static_cast<OdRow*>(&out), p.row, sizeof(OdRow));
  out.index = static_cast<uint16_t>(out.index + p.n);
  // (below values_size, so within the 15 bits)
  out.loc = static_cast<uint16_t>(out.loc + p.n * p.stride) & kOdLocMask;
  out.def = def_at(p);
  return out;
}

// The searches step over byte offsets of the rows (multiples of the row
// size, a power of two): the middle row is a shift and a mask away, with no
// row-number multiply per step (a loop on the AVR). Same rows visited as a
// search over row numbers: the middle is 8 * floor((lo + hi) / 2) either way.
// Offsets are 16-bit: an OD of at most 8,191 rows.
static_assert((sizeof(OdRow) & (sizeof(OdRow) - 1)) == 0, "row size a power of two");
static const uint16_t kRowMask = static_cast<uint16_t>(~(sizeof(OdRow) - 1));

// The records' rows are not in def_.rows: a record's index leads to its
// rows (a kind's records are consecutive, each rows[kind] long), whose few
// sub-indices (at most 9) are compared in turn.
uint16_t ObjectDictionary::find_record(uint16_t index, uint8_t sub) const {
  const uint16_t number = od_record_number(index);
  if (number >= kOdRecordsPerKind) return kNoRow;
  const OdRecords* records = def_.records;
  const uint8_t kind = od_record_kind(index);
  const uint8_t rows = flash_read(&records->rows[kind]);
  uint16_t row = static_cast<uint16_t>(def_.record_first + flash_read(&records->base[kind]) + number * rows);
  for (uint8_t j = 0; j < rows; ++j, ++row) {
    if (sub_of(row) == sub) return row;
  }
  return kNoRow;
}

// A row number from a place in def_.rows (which has no record rows).
static uint16_t plain_to_row(const OdDefinition& def, uint16_t plain) {
  return plain < def.record_first ? plain : static_cast<uint16_t>(plain + def.record_count);
}

#if MB2CO_CONFIG_OD_DIRECT_GET
uint16_t ObjectDictionary::search(uint16_t index, uint8_t sub) const {
#else
uint16_t ObjectDictionary::find(uint16_t index, uint8_t sub) const {
#endif
  if (static_cast<uint16_t>(index - kOdRecordFirst) < kOdRecordEnd - kOdRecordFirst) {
    return find_record(index, sub);
  }
  const uint8_t* rows = reinterpret_cast<const uint8_t*>(def_.rows);
  uint16_t lo = 0;
  uint16_t hi = static_cast<uint16_t>((def_.row_count - def_.record_count) * sizeof(OdRow));
  while (lo < hi) {
    const uint16_t mid = static_cast<uint16_t>(((lo + hi) / 2) & kRowMask);
    const OdRow* r = reinterpret_cast<const OdRow*>(rows + mid);
    const uint16_t i = flash_read(&r->index);
    const uint8_t s = i == index ? flash_read(&r->sub) : 0;
    if (i == index && s == sub) return plain_to_row(def_, static_cast<uint16_t>(mid / sizeof(OdRow)));
    if (i < index || (i == index && s < sub)) {
      lo = static_cast<uint16_t>(mid + sizeof(OdRow));
    } else {
      hi = mid;
    }
  }
  return kNoRow;
}

void ObjectDictionary::find_rows(const uint16_t* indices, uint8_t count, uint16_t* rows) const {
  for (uint8_t i = 0; i < count; ++i) rows[i] = find(flash_read(&indices[i]), 0);
}

// Every index begins with sub 0 (od_rows_sorted).
uint16_t ObjectDictionary::first_row(uint16_t index) const {
  return find(index, 0);
}

bool ObjectDictionary::has_index(uint16_t index) const {
  return find(index, 0) != kNoRow;
}

uint8_t ObjectDictionary::type_bits(uint8_t type) const {
  const uint16_t r = type == 0 || type >= kOdTypeCount ? kNoRow : find(type, 0);
  return r == kNoRow ? 0 : static_cast<uint8_t>(def_at(place(r)));
}

uint16_t ObjectDictionary::capacity_of(uint16_t row) const {
#if MB2CO_CONFIG_OD_DIRECT_GET
  if (row < direct_rows_ && direct_[row].numeric != 0) return direct_[row].numeric;
#endif
  const Place p = place(row);
  if (flash_read(&p.row->attr) & kAttrString) return static_cast<uint16_t>(def_at(p) >> 16);
  return numeric_size(p.row);
}

uint16_t ObjectDictionary::size_of(uint16_t row) const {
#if MB2CO_CONFIG_OD_DIRECT_GET
  if (row < direct_rows_ && direct_[row].numeric != 0) return direct_[row].numeric;
#endif
  const Place p = place(row);
  if (!(flash_read(&p.row->attr) & kAttrString)) return numeric_size(p.row);
  return string_length(p);
}

// A VISIBLE_STRING ends at its first NUL; OCTET_STRING, UNICODE_STRING
// and DOMAIN are always their whole capacity (fixed length: a row holds no
// length of its own).
uint16_t ObjectDictionary::string_length(Place pl) const {
  const OdRow* e = pl.row;
  const uint8_t a = flash_read(&e->attr);
  const uint32_t def = def_at(pl);
  const uint16_t cap = static_cast<uint16_t>(def >> 16);
  uint16_t n = 0;
  // (byte-run types are below 10h: the type's low nibble is all of it)
  if ((flash_read(reinterpret_cast<const uint8_t*>(e) + kOdEntryTypeHookOffset) & 0x0F) != kVisibleString)
    return cap;
  if (a & kAttrRam) {
    const uint8_t* p = value_at(pl);
    while (n < cap && p[n] != 0) ++n;
  } else {
    const char* p = def_.strings + (def & 0xFFFFu);
    while (n < cap && flash_byte(p + n) != 0) ++n;
  }
  return n;
}

uint32_t ObjectDictionary::constant_at(Place p) const {
  const uint32_t def = def_at(p);
  return (flash_read(&p.row->attr) & kAttrNodeId) ? def + node_id_ : def;
}

// get() and set() are on every path (services, PDOs, Modbus): they read the
// three fields they need straight from the row and move the value with one
// memcpy (values are little-endian, like both targets). With the direct
// table (MB2CO_CONFIG_OD_DIRECT_GET) get() reads a numeric RAM row inline
// (od.h) and comes here for the rest.
#if MB2CO_CONFIG_OD_DIRECT_GET
uint32_t ObjectDictionary::decoded(uint16_t row) const {
#else
uint32_t ObjectDictionary::get(uint16_t row) const {
#endif
  const Place pl = place(row);
  const uint8_t a = flash_read(&pl.row->attr);
  if (!(a & kAttrRam)) return constant_at(pl);
  // Strings (their current length decides) out of line: the numeric path
  // then needs no register saves on the AVR.
  const uint16_t n = (a & kAttrString) ? string_length(pl) : numeric_size(pl.row);
  const uint8_t* p = value_at(pl);
  if (n == 1) return p[0];
  if (n == 2) {
    uint16_t v;
    memcpy(&v, p, 2);
    return v;
  }
  uint32_t v = 0;
  memcpy(&v, p, n < 4 ? n : 4);  // 3, 4, or the low bytes of a wider value
  return v;
}

bool ObjectDictionary::set(uint16_t row, uint32_t value) {
#if MB2CO_CONFIG_OD_DIRECT_GET
  // A numeric RAM row in the direct table: compared and stored where it is
  // (its `numeric` bytes, none beyond).
  if (row < kDirectRows && direct_[row].mask != 0) {
    const Direct& d = direct_[row];
    uint32_t old;
    memcpy(&old, values_ + d.offset, 4);
    if (((old ^ value) & d.mask) == 0) return false;
    memcpy(values_ + d.offset, &value, d.numeric);  // little-endian, as on the bus
    touch();
    return true;
  }
#endif
  const Place pl = place(row);
  if ((flash_read(&pl.row->attr) & (kAttrRam | kAttrString)) != kAttrRam) return false;
  uint8_t* p = value_at(pl);
  const uint8_t n = numeric_size(pl.row);
  bool changed = false;
  for (uint8_t i = 0; i < n; ++i, value >>= 8) {  // little-endian, as on the bus
    const uint8_t b = static_cast<uint8_t>(value);
    changed = changed || p[i] != b;
    p[i] = b;
  }
  if (changed) touch();
  return changed;
}

uint8_t* ObjectDictionary::ram(uint16_t row) {
  touch();
  return const_cast<uint8_t*>(static_cast<const ObjectDictionary*>(this)->ram(row));
}

const uint8_t* ObjectDictionary::ram(uint16_t row) const {
  const Place p = place(row);
  return (flash_read(&p.row->attr) & kAttrRam) ? value_at(p) : nullptr;
}

uint16_t ObjectDictionary::copy_out(uint16_t row, uint8_t* buf, uint16_t cap) const {
#if MB2CO_CONFIG_OD_DIRECT_GET
  // A numeric RAM row in the direct table: its bytes where they are.
  if (row < kDirectRows && direct_[row].mask != 0) {
    const uint16_t n = direct_[row].numeric < cap ? direct_[row].numeric : cap;
    memcpy(buf, values_ + direct_[row].offset, n);
    return n;
  }
#endif
  const Place pl = place(row);
  const uint8_t a = flash_read(&pl.row->attr);
  uint16_t n = size_of(row);
  if (n > cap) n = cap;
  if (a & kAttrRam) {
    memcpy(buf, value_at(pl), n);
  } else if (a & kAttrString) {
    const char* p = def_.strings + (def_at(pl) & 0xFFFFu);
    for (uint16_t i = 0; i < n; ++i) buf[i] = flash_byte(p + i);
  } else {
    const uint32_t v = get(row);
    memcpy(buf, &v, n > 4 ? 4 : n);
  }
  return n;
}

// Every row is visited (a reset restores most of the OD): single fields,
// the default read only for the rows restored.
void ObjectDictionary::restore_defaults(uint16_t from_index, uint16_t to_index) {
  touch();
  for (uint16_t r = 0; r < def_.row_count; ++r) {
    const Place p = place(r);
    const OdRow* e = p.row;
    const uint16_t index = static_cast<uint16_t>(flash_read(&e->index) + p.n);
    const uint8_t a = flash_read(&e->attr);
    if (index < from_index || index > to_index || !(a & kAttrRam)) continue;
    if (a & kAttrString) {
      const uint32_t def = def_at(p);
      const uint16_t cap = static_cast<uint16_t>(def >> 16);
      const char* src = def_.strings + (def & 0xFFFFu);
      uint8_t* dst = value_at(p);
      uint16_t i = 0;
      for (; i < cap && flash_byte(src + i) != 0; ++i) dst[i] = flash_byte(src + i);
      for (; i < cap; ++i) dst[i] = 0;
    } else {
      // The default, node id added, stored as set() would (touched above).
      uint32_t v = constant_at(p);
      uint8_t* dst = value_at(p);
      for (uint8_t i = numeric_size(e); i != 0; --i, v >>= 8) *dst++ = static_cast<uint8_t>(v);
    }
  }
}

SdoAbort ObjectDictionary::check_read(uint16_t index, uint8_t sub, uint16_t* row) const {
  const uint16_t r = find(index, sub);
  if (r == kNoRow) return has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  if (!(attr(r) & kAttrRead)) return kAbortWriteOnly;
  *row = r;
  return kSdoOk;
}

SdoAbort ObjectDictionary::read(uint16_t index, uint8_t sub, uint8_t* buf, uint16_t cap,
                                uint16_t* len) const {
  uint16_t r = kNoRow;
  const SdoAbort abort = check_read(index, sub, &r);
  if (abort != kSdoOk) return abort;
  if (size_of(r) > cap) return kAbortTooLong;
  *len = copy_out(r, buf, cap);
  return kSdoOk;
}

SdoAbort ObjectDictionary::check_write(uint16_t index, uint8_t sub, uint16_t* row) const {
  const uint16_t r = find(index, sub);
  if (r == kNoRow) return has_index(index) ? kAbortNoSubindex : kAbortNoObject;
  if (!(attr(r) & kAttrWrite)) return kAbortReadOnly;
  *row = r;
  return kSdoOk;
}

SdoAbort ObjectDictionary::check_limits(const OdEntry& e, const uint8_t* data, uint16_t len) const {
  const uint8_t type = e.data_type();
  if (type == kBoolean && data[0] > 1) return kAbortInvalidValue;
  for (uint8_t i = 0; i < def_.limit_count; ++i) {
    // Single fields from flash: most limits are not this entry's.
    const OdLimit* lim = &def_.limits[i];
    if (flash_read(&lim->index) != e.index || flash_read(&lim->sub) != e.sub) continue;
    // The value as the limits read it (OdLimitValue, 32 bits on the AVR: no
    // 64-bit code there; od_define.h checks that no limited entry is wider):
    // sign- or zero-extended from `len` bytes; a REAL as its ordered key
    // (od_real_limit: the magnitude, negated for a negative real).
    const uint8_t kind = static_cast<uint8_t>(flash_read(&kOdTypeInfo[type]) >> 4);
    const bool negative = kind != kKindUnsigned && (data[len - 1] & 0x80);
    uint8_t bytes[sizeof(OdLimitValue)];
    memset(bytes, kind == kKindSigned && negative ? 0xFF : 0x00, sizeof bytes);
    memcpy(bytes, data, len);  // little-endian, like both targets
    if (kind == kKindReal) bytes[len - 1] &= 0x7F;
    OdLimitValue v;
    memcpy(&v, bytes, sizeof v);
    // An unsigned value above the signed maximum is above every maximum.
    if (kind == kKindUnsigned && v < 0) return kAbortValueTooHigh;
    if (kind == kKindReal && negative) v = -v;
    // The bounds as their bits: one flash read each (OdLimitBits).
    if (v < static_cast<OdLimitValue>(flash_read(reinterpret_cast<const OdLimitBits*>(&lim->min)))) {
      return kAbortValueTooLow;
    }
    if (v > static_cast<OdLimitValue>(flash_read(reinterpret_cast<const OdLimitBits*>(&lim->max)))) {
      return kAbortValueTooHigh;
    }
  }
  return kSdoOk;
}

void ObjectDictionary::store(const OdEntry& e, const uint8_t* data, uint16_t len, bool tracked) {
  if (tracked) touch();
  uint8_t* p = values_ + e.loc;
  memcpy(p, data, len);
  if (e.attr & kAttrString) {
    const uint16_t cap = static_cast<uint16_t>(e.def >> 16);
    if (len < cap) memset(p + len, 0, cap - len);
  }
}

SdoAbort ObjectDictionary::write(uint16_t index, uint8_t sub, const uint8_t* data, uint16_t len) {
  uint16_t r = kNoRow;
  const SdoAbort abort = check_write(index, sub, &r);
  if (abort != kSdoOk) return abort;
  return write_row(r, data, len);
}

SdoAbort ObjectDictionary::write_row(uint16_t r, const uint8_t* data, uint16_t len, bool apply) {
  const OdEntry e = entry(r);
  const uint16_t cap = capacity_of(r);
  if (len > cap) return kAbortTooLong;
  // Every type but VISIBLE_STRING has its fixed length (string_length()).
  if (len < cap && e.data_type() != kVisibleString) return kAbortTooShort;
  if (!(e.attr & kAttrString)) {
    const SdoAbort abort = check_limits(e, data, len);
    if (abort != kSdoOk) return abort;
  }
  // The entry's handler, once the node is bound (an OD without its node,
  // e.g. a tool's, checks and stores only).
  if (e.hook != kHookNone && owners_[kOdOwnerNode] != nullptr) {
    const HookResult verdict = def_.call_handler(owners_, e.hook, apply, e.index, e.sub, data);
    if (!verdict.store()) return verdict.abort();
  }
  store(e, data, len, apply);
  return kSdoOk;
}

void ObjectDictionary::put_value(PdoMapped<uint8_t>& entry, uint8_t value) {
  if (entry.value_ == value) return;
  entry.value_ = value;
  touch();
}

}  // namespace canopen
}  // namespace mb2co
