// The kinds of damaged saved-parameter storage of issue 16 item 6, made from a
// good image, for the tests of every program that loads parameters (the
// gateway in-process, mb2co-node's --eeprom file). Written from the layout
// that shared/canopen/param_storage.cpp documents, not from its code: two
// slots at 0 and 512, each magic "C2" (4332h) | sequence | payload length |
// payload | CRC-16/MODBUS over payload then header, low byte first.
//
// The good image holds two sets: set A (older, slot 0, sequence 1), then set
// B (newer, slot 1, sequence 2). Bytes beyond the image read as FFh, as an
// erased EEPROM does (mb2co-node reads its file so), so a cut file is an
// image whose tail is erased.
#pragma once
#include <stdint.h>

#include <random>
#include <vector>

#include "rtu_frames.h"  // crc16_bitwise: CRC-16/MODBUS written from its definition

namespace mb2co {
namespace test {
namespace storage_damage {

const size_t kSlot = 512;
const size_t kHeader = 6;

/// What a program must make of a damaged image.
enum class Verdict {
  kNoSet,     ///< a blank medium (nothing saved): defaults, nothing reported
  kDefaults,  ///< every set damaged: defaults, damage reported
  kOlderSet,  ///< the newer set damaged: set A in force, damage reported
};

inline size_t payload_length(const std::vector<uint8_t>& image, size_t slot) {
  return image[slot + 4] | (image[slot + 5] << 8);
}

/// A right CRC for the slot at `slot` after its payload was changed.
inline void reseal(std::vector<uint8_t>& image, size_t slot) {
  const size_t len = payload_length(image, slot);
  std::vector<uint8_t> covered(image.begin() + static_cast<long>(slot + kHeader),
                               image.begin() + static_cast<long>(slot + kHeader + len));
  covered.insert(covered.end(), image.begin() + static_cast<long>(slot),
                 image.begin() + static_cast<long>(slot + kHeader));
  const uint16_t crc = crc16_bitwise(covered.data(), covered.size());
  image[slot + kHeader + len] = static_cast<uint8_t>(crc & 0xFF);
  image[slot + kHeader + len + 1] = static_cast<uint8_t>(crc >> 8);
}

/// The marker value the good sets carry in a 16-bit entry with limits (the
/// tests save 2000h/6 debounce = 499 ms, limit 1..500); kBeyond is 501.
const uint16_t kMarker = 499;
const uint16_t kBeyond = 501;

/// Replaces the marker in the payload of `slot` by a value beyond the
/// entry's limits and reseals the slot: the CRC is right, the value is not
/// allowed. False when the marker is not found exactly once.
inline bool put_beyond_limits(std::vector<uint8_t>& image, size_t slot) {
  const size_t len = payload_length(image, slot);
  size_t found = 0, at = 0;
  for (size_t i = slot + kHeader; i + 1 < slot + kHeader + len; ++i) {
    if (image[i] == (kMarker & 0xFF) && image[i + 1] == (kMarker >> 8)) {
      ++found;
      at = i;
    }
  }
  if (found != 1) return false;
  image[at] = kBeyond & 0xFF;
  image[at + 1] = kBeyond >> 8;
  reseal(image, slot);
  return true;
}

struct Kind {
  const char* name;
  Verdict verdict;
  /// Damages the good image (returns false if it could not).
  bool (*apply)(std::vector<uint8_t>& image);
};

inline bool cut(std::vector<uint8_t>& image, size_t size) {
  image.resize(size);
  return true;
}
inline bool flip(std::vector<uint8_t>& image, size_t at) {
  image[at] ^= 0x01;
  return true;
}
inline size_t crc_at(const std::vector<uint8_t>& image, size_t slot) {
  return slot + kHeader + payload_length(image, slot);
}

/// The kinds of a damaged or blank image (the unusable paths are the
/// program's own: a directory, a missing directory, a read-only file).
inline const std::vector<Kind>& kinds() {
  static const std::vector<Kind> all = {
      {"empty", Verdict::kNoSet, [](std::vector<uint8_t>& im) { return cut(im, 0); }},
      {"cut inside the first header", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) { return cut(im, 3); }},
      {"cut inside the older set", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) { return cut(im, kHeader + payload_length(im, 0) / 2); }},
      {"cut inside the newer set", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return cut(im, kSlot + kHeader + payload_length(im, kSlot) / 2); }},
      {"cut before the last CRC byte", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return cut(im, crc_at(im, kSlot) + 1); }},
      {"magic bit flipped in both headers", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) { return flip(im, 0) && flip(im, kSlot); }},
      {"sequence bit flipped in the newer header", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return flip(im, kSlot + 2); }},
      {"length bit flipped in both headers", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) { return flip(im, 4) && flip(im, kSlot + 4); }},
      {"CRC bit flipped in the newer set", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return flip(im, crc_at(im, kSlot)); }},
      {"data bit flipped in both sets", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) { return flip(im, kHeader + 20) && flip(im, kSlot + kHeader + 20); }},
      {"data bit flipped in the newer set", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return flip(im, kSlot + kHeader + 20); }},
      {"all FF (erased)", Verdict::kNoSet,
       [](std::vector<uint8_t>& im) {
         im.assign(1024, 0xFF);
         return true;
       }},
      {"all 00", Verdict::kNoSet,
       [](std::vector<uint8_t>& im) {
         im.assign(1024, 0x00);
         return true;
       }},
      {"random bytes", Verdict::kDefaults,
       [](std::vector<uint8_t>& im) {
         std::mt19937 rng(16);
         im.resize(1024);
         for (uint8_t& b : im) b = static_cast<uint8_t>(rng());
         return true;
       }},
      {"a value beyond its limits under a right CRC", Verdict::kOlderSet,
       [](std::vector<uint8_t>& im) { return put_beyond_limits(im, kSlot); }},
  };
  return all;
}

}  // namespace storage_damage
}  // namespace test
}  // namespace mb2co
