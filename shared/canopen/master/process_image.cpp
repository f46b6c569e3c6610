#include "canopen/master/process_image.h"

#include <string.h>

#include "canopen/frame_out.h"
#include "canopen/pdo_map.h"

namespace mb2co {
namespace canopen {

// Copies `bits` bits from src (starting at bit src_at) to dst (at dst_at),
// keeping dst's other bits; bit i of a buffer is bit i%8 of byte i/8.
static void move_bits(uint8_t* dst, uint8_t dst_at, const uint8_t* src, uint8_t src_at, uint8_t bits) {
  for (uint8_t i = 0; i < bits; ++i) {
    const uint8_t s = static_cast<uint8_t>(src_at + i);
    const uint8_t t = static_cast<uint8_t>(dst_at + i);
    const uint8_t mask = static_cast<uint8_t>(1u << (t % 8));
    if ((static_cast<unsigned>(src[s / 8]) >> (s % 8)) & 1u) {
      dst[t / 8] = static_cast<uint8_t>(dst[t / 8] | mask);
    } else {
      dst[t / 8] = static_cast<uint8_t>(dst[t / 8] & ~mask);
    }
  }
}

// Clears the bits of an 8-byte value above `bits`.
static void mask_value(uint8_t* data, uint8_t bits) {
  for (uint8_t i = 0; i < 8; ++i) {
    const int16_t keep = static_cast<int16_t>(bits - i * 8);
    if (keep <= 0) {
      data[i] = 0;
    } else if (keep < 8) {
      data[i] = static_cast<uint8_t>(data[i] & ((1u << keep) - 1u));
    }
  }
}

// CiA 301 §7.4.7.1: the dummy data types 0002h-0007h and their lengths.
static uint8_t dummy_bits(uint16_t index) {
  static const uint8_t kBits[] MB2CO_FLASH = {8, 16, 32, 8, 16, 32};  // INT8..INT32, UNSIGNED8..32
  return flash_read(&kBits[index - 0x0002]);
}

uint32_t ImageEntry::u32() const {
  return le32(data);
}

int32_t ImageEntry::s32() const {
  const uint32_t v = u32();
  if (bits == 0 || bits >= 32) return static_cast<int32_t>(v);
  const uint32_t sign = 1u << (bits - 1);
  return static_cast<int32_t>((v ^ sign) - sign);
}

ImagePdo* ProcessImageCore::find_pdo(uint8_t node_id, uint8_t n, bool rpdo) {
  for (uint8_t i = 0; i < max_pdos_; ++i) {
    ImagePdo& p = pdos_[i];
    if (p.node_id == node_id && node_id != 0 && p.n == n && ((p.flags & kReceive) != 0) == rpdo) return &p;
  }
  return nullptr;
}

const ImagePdo* ProcessImageCore::pdo(uint8_t node_id, uint8_t n, bool rpdo) const {
  return const_cast<ProcessImageCore*>(this)->find_pdo(node_id, n, rpdo);
}

uint8_t ProcessImageCore::find_entry(uint8_t node_id, uint16_t index, uint8_t sub) const {
  for (uint8_t i = 0; i < max_entries_; ++i) {
    const ImageEntry& e = entries_[i];
    if (e.node_id == node_id && node_id != 0 && e.index == index && e.sub == sub) return i;
  }
  return ImagePdo::kDummy;
}

const ImageEntry* ProcessImageCore::find(uint8_t node_id, uint16_t index, uint8_t sub) const {
  const uint8_t i = find_entry(node_id, index, sub);
  return i == ImagePdo::kDummy ? nullptr : &entries_[i];
}

bool ProcessImageCore::configure(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping,
                                 uint8_t count, uint8_t flags) {
  if (node_id == 0 || node_id > 127 || cob_id > 0x7FFu || count == 0 || count > kPdoMaxMapped) return false;
  // Check everything before changing anything: lengths, and room for the
  // objects not mirrored yet (an object mapped twice needs one slot).
  uint16_t total = 0;
  uint8_t needed = 0;
  for (uint8_t k = 0; k < count; ++k) {
    const uint32_t m = mapping[k];
    if (map_bits(m) == 0) return false;
    total = static_cast<uint16_t>(total + map_bits(m));
    if (map_is_dummy(m)) {
      if (map_bits(m) != dummy_bits(map_index(m))) return false;
      continue;
    }
    bool seen = find_entry(node_id, map_index(m), map_sub(m)) != ImagePdo::kDummy;
    for (uint8_t j = 0; j < k && !seen; ++j) seen = (mapping[j] & 0xFFFFFF00u) == (m & 0xFFFFFF00u);
    if (!seen) ++needed;
  }
  if (total > 64) return false;
  const bool rpdo = (flags & kReceive) != 0;
  ImagePdo* p = find_pdo(node_id, n, rpdo);
  for (uint8_t i = 0; i < max_pdos_ && p == nullptr; ++i) {
    if (pdos_[i].node_id == 0) p = &pdos_[i];
  }
  uint8_t free_entries = 0;
  for (uint8_t i = 0; i < max_entries_; ++i)
    free_entries = static_cast<uint8_t>(free_entries + (entries_[i].node_id == 0));
  if (p == nullptr || needed > free_entries) return false;

  *p = ImagePdo();
  p->cob_id = cob_id;
  p->node_id = node_id;
  p->n = n;
  p->flags = flags;
  p->count = count;
  p->bytes = static_cast<uint8_t>((total + 7) / 8);
  for (uint8_t k = 0; k < count; ++k) {
    const uint32_t m = mapping[k];
    p->bits[k] = map_bits(m);
    if (map_is_dummy(m)) {
      p->entry[k] = ImagePdo::kDummy;
      continue;
    }
    uint8_t e = find_entry(node_id, map_index(m), map_sub(m));
    if (e == ImagePdo::kDummy) {
      for (e = 0; entries_[e].node_id != 0; ++e) {
      }
      entries_[e] = ImageEntry();
      entries_[e].node_id = node_id;
      entries_[e].index = map_index(m);
      entries_[e].sub = map_sub(m);
    }
    if (map_bits(m) > entries_[e].bits) entries_[e].bits = map_bits(m);
    p->entry[k] = e;
  }
  return true;
}

bool ProcessImageCore::configure_tpdo(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping,
                                      uint8_t count) {
  return configure(node_id, n, cob_id, mapping, count, 0);
}

bool ProcessImageCore::configure_rpdo(uint8_t node_id, uint8_t n, uint16_t cob_id, const uint32_t* mapping,
                                      uint8_t count, RpdoTrigger trigger) {
  if (trigger > kRpdoOnChange) return false;
  return configure(node_id, n, cob_id, mapping, count,
                   static_cast<uint8_t>(kReceive | (trigger << kTriggerShift)));
}

bool ProcessImageCore::on_frame(const CanFrame& f, uint32_t now_us) {
  if (f.rtr() || f.extended()) return false;
  bool consumed = false;
  for (uint8_t i = 0; i < max_pdos_; ++i) {
    const ImagePdo& p = pdos_[i];
    if (p.node_id == 0 || (p.flags & kReceive) || p.cob_id != f.id) continue;
    consumed = true;
    if (f.dlc < p.bytes) {
      if (pdos_[i].length_errors != 0xFFFF) ++pdos_[i].length_errors;
      if (length_errors_ != 0xFFFF) ++length_errors_;
      continue;
    }
    uint8_t at = 0;
    for (uint8_t k = 0; k < p.count; ++k) {
      if (p.entry[k] != ImagePdo::kDummy) {
        ImageEntry& e = entries_[p.entry[k]];
        memset(e.data, 0, sizeof e.data);
        move_bits(e.data, 0, f.data, at, p.bits[k]);
        e.updated_us = now_us;
        if (e.updates != 0xFFFF) ++e.updates;
      }
      at = static_cast<uint8_t>(at + p.bits[k]);
    }
  }
  return consumed;
}

bool ProcessImageCore::set_bytes(uint8_t node_id, uint16_t index, uint8_t sub, const uint8_t* data,
                                 uint8_t len) {
  const uint8_t i = find_entry(node_id, index, sub);
  if (i == ImagePdo::kDummy || len > 8) return false;
  ImageEntry& e = entries_[i];
  uint8_t v[8] = {};
  memcpy(v, data, len);
  mask_value(v, e.bits);
  if (memcmp(v, e.data, sizeof v) == 0) return true;
  memcpy(e.data, v, sizeof v);
  for (uint8_t p = 0; p < max_pdos_; ++p) {
    ImagePdo& pdo = pdos_[p];
    if (pdo.node_id == 0 || ((pdo.flags & kTriggerMask) >> kTriggerShift) != kRpdoOnChange) continue;
    for (uint8_t k = 0; k < pdo.count; ++k) {
      if (pdo.entry[k] == i) pdo.flags = static_cast<uint8_t>(pdo.flags | kPending);
    }
  }
  return true;
}

bool ProcessImageCore::set(uint8_t node_id, uint16_t index, uint8_t sub, uint32_t value) {
  uint8_t v[4];
  put_le32(v, value);
  return set_bytes(node_id, index, sub, v, sizeof v);
}

bool ProcessImageCore::send(ImagePdo& p, const CanSink& sink) {
  uint8_t data[8] = {};
  uint8_t at = 0;
  for (uint8_t k = 0; k < p.count; ++k) {
    if (p.entry[k] != ImagePdo::kDummy) move_bits(data, at, entries_[p.entry[k]].data, 0, p.bits[k]);
    at = static_cast<uint8_t>(at + p.bits[k]);
  }
  if (send_frame(sink, p.cob_id, p.bytes, data)) {
    p.flags = static_cast<uint8_t>(p.flags & ~kPending);
    return true;
  }
  if (send_failures_ != 0xFFFF) ++send_failures_;
  return false;
}

bool ProcessImageCore::send_rpdo(uint8_t node_id, uint8_t n, const CanSink& sink) {
  ImagePdo* p = find_pdo(node_id, n, true);
  return p != nullptr && send(*p, sink);
}

void ProcessImageCore::on_sync(const CanSink& sink) {
  for (uint8_t i = 0; i < max_pdos_; ++i) {
    ImagePdo& p = pdos_[i];
    if (p.node_id != 0 && ((p.flags & kTriggerMask) >> kTriggerShift) == kRpdoOnSync) send(p, sink);
  }
}

void ProcessImageCore::process(uint32_t now_us, const CanSink& sink) {
  (void)now_us;  // no timers yet (an inhibit time would use it)
  for (uint8_t i = 0; i < max_pdos_; ++i) {
    if (pdos_[i].node_id != 0 && (pdos_[i].flags & kPending)) send(pdos_[i], sink);
  }
}

void ProcessImageCore::next_deadline(NextDeadline& d) const {
  for (uint8_t i = 0; i < max_pdos_; ++i) {
    if (pdos_[i].node_id != 0 && (pdos_[i].flags & kPending)) return d.now();
  }
}

}  // namespace canopen
}  // namespace mb2co
