#include "canopen/od_lab_api.h"

#include <string.h>

namespace mb2co {
namespace canopen {

namespace {
ObjectDictionary* g_od = nullptr;

// Rows [first, end) of `index`, or an error.
int object_rows(uint16_t index, uint16_t* first, uint16_t* end) {
  if (g_od == nullptr) return kOdLabNotBound;
  const uint16_t r = g_od->first_row(index);
  if (r == ObjectDictionary::kNoRow) return kOdLabNoObject;
  uint16_t e = r;
  while (e < g_od->row_count() && g_od->entry(e).index == index) ++e;
  *first = r;
  *end = e;
  return 0;
}

int subentry_row(uint16_t index, uint8_t sub, uint16_t* row) {
  if (g_od == nullptr) return kOdLabNotBound;
  *row = g_od->find(index, sub);
  if (*row != ObjectDictionary::kNoRow) return 0;
  return g_od->has_index(index) ? kOdLabNoSubentry : kOdLabNoObject;
}

// Strings are stored to their capacity; the lab's data for them is that many
// bytes (NUL-padded), so read and write layouts agree.
uint16_t lab_size(uint16_t row) {
  return (g_od->entry(row).attr & kAttrString) ? g_od->capacity_of(row) : g_od->size_of(row);
}

// `apply` false: only decide (ObjectDictionary::write_row), the value stored
// untracked for the caller to put back; the device's own read-only entries
// are not touched then.
int write_row(uint16_t row, const uint8_t* data, bool apply = true) {
  const OdEntry e = g_od->entry(row);
  if (!(e.attr & kAttrRam)) return kOdLabReadOnly;
  uint16_t n = lab_size(row);
  if (e.attr & kAttrString) n = static_cast<uint16_t>(strnlen(reinterpret_cast<const char*>(data), n));
  if (e.attr & kAttrWrite) {
    return g_od->write_row(row, data, n, apply) == kSdoOk ? 0 : kOdLabRefused;
  }
  if (apply) memcpy(g_od->ram(row), data, n);  // the device's own read-only entry (inputs)
  return 0;
}
}  // namespace

void od_bind(ObjectDictionary* od) {
  g_od = od;
}

int od_getsize_subentry(uint16_t index, uint8_t sub, uint8_t* size) {
  uint16_t row = 0;
  const int rc = subentry_row(index, sub, &row);
  if (rc != 0) return rc;
  const uint16_t n = lab_size(row);
  if (n > 255) return kOdLabTooBig;
  *size = static_cast<uint8_t>(n);
  return 0;
}

int od_getsize_object(uint16_t index, uint8_t* size) {
  uint16_t first = 0, end = 0;
  const int rc = object_rows(index, &first, &end);
  if (rc != 0) return rc;
  uint16_t total = 0;
  for (uint16_t r = first; r < end; ++r) total = static_cast<uint16_t>(total + lab_size(r));
  if (total > 255) return kOdLabTooBig;
  *size = static_cast<uint8_t>(total);
  return 0;
}

int od_read_subentry(uint16_t index, uint8_t sub, uint8_t* data, uint8_t* size) {
  uint16_t row = 0;
  int rc = subentry_row(index, sub, &row);
  if (rc != 0) return rc;
  rc = od_getsize_subentry(index, sub, size);
  if (rc != 0) return rc;
  memset(data, 0, *size);
  g_od->copy_out(row, data, *size);
  return 0;
}

int od_read_object(uint16_t index, uint8_t* data, uint8_t* size) {
  uint16_t first = 0, end = 0;
  int rc = object_rows(index, &first, &end);
  if (rc != 0) return rc;
  rc = od_getsize_object(index, size);
  if (rc != 0) return rc;
  uint16_t at = 0;
  for (uint16_t r = first; r < end; ++r) {
    const uint16_t n = lab_size(r);
    memset(data + at, 0, n);
    g_od->copy_out(r, data + at, n);
    at = static_cast<uint16_t>(at + n);
  }
  return 0;
}

int od_write_subentry(uint16_t index, uint8_t sub, const uint8_t* data) {
  uint16_t row = 0;
  const int rc = subentry_row(index, sub, &row);
  return rc != 0 ? rc : write_row(row, data);
}

int od_write_object(uint16_t index, const uint8_t* data) {
  uint16_t first = 0, end = 0;
  int rc = object_rows(index, &first, &end);
  if (rc != 0) return rc;
  uint8_t total = 0;
  rc = od_getsize_object(index, &total);
  if (rc != 0) return rc;
  // Like a Modbus write of several registers: every sub-entry is decided
  // first (each on the ones before it, stored untracked), all put back, and
  // only when all are accepted written for real, hooks acting. A refused
  // object leaves every value and the services' state as they were. The old
  // values: 255 B of stack (call it from the main loop, not from deep
  // inside). Const sub-entries (e.g. sub 0 counts) are skipped: their bytes
  // are ignored.
  uint8_t old[255];
  uint16_t at = 0;
  for (uint16_t r = first; r < end; ++r) {
    const uint16_t n = lab_size(r);
    if (g_od->entry(r).attr & kAttrRam) memcpy(old + at, g_od->ram_untracked(r), n);
    at = static_cast<uint16_t>(at + n);
  }
  for (int apply = 0; apply < 2; ++apply) {
    at = 0;
    rc = 0;
    for (uint16_t r = first; r < end && rc == 0; ++r) {
      if (g_od->entry(r).attr & kAttrRam) rc = write_row(r, data + at, apply != 0);
      at = static_cast<uint16_t>(at + lab_size(r));
    }
    if (apply == 0) {  // the check step's values go back, untracked
      uint16_t back = 0;
      for (uint16_t k = first; k < end; ++k) {
        const uint16_t m = lab_size(k);
        if (g_od->entry(k).attr & kAttrRam) memcpy(g_od->ram_untracked(k), old + back, m);
        back = static_cast<uint16_t>(back + m);
      }
    }
    if (rc != 0) return rc;
  }
  return 0;
}

}  // namespace canopen
}  // namespace mb2co
