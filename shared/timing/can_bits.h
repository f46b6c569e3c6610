// Length in bits of a classic CAN data frame (seed 000 §2.10): without stuff
// bits, with worst-case stuffing by either convention, and exactly for one
// concrete frame (CRC-15 computed, stuff bits counted as a controller would).
// Every length counts SOF .. EOF plus the 3-bit interframe space, because the
// bus is not free for the next frame before the IFS ends.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace timing {

/// Which worst-case stuffing bound to use.
enum class WorstCase : uint8_t {
  /// Seed 000 §2.10: floor(S/5) stuff bits over the S bits from SOF through
  /// the CRC counted as 16 bits (delimiter included): 130 bits for 8 bytes.
  /// Undercounts: a stuff bit itself starts the next run, so a stuff bit can
  /// follow every 4 bits after the first 5.
  kCourse,
  /// Davis, Burns, Bril, Lukkien 2007: floor((g + 8n - 1)/4) stuff bits with
  /// g = 34 (11-bit IDs) or 54 (29-bit): 55 + 10n and 80 + 10n bits.
  kDavis,
};

/// Data bytes a DLC stands for: 0..8 (ISO 11898: DLC 9..15 also mean 8).
inline uint8_t dlc_bytes(uint8_t dlc) {
  return dlc > 8 ? uint8_t{8} : dlc;
}

/// Bits SOF .. IFS without stuff bits: 47 + 8n (11-bit ID), 67 + 8n (29-bit).
uint16_t frame_bits_unstuffed(bool extended, uint8_t dlc);

/// Bits exposed to stuffing, SOF through the 15-bit CRC sequence:
/// 34 + 8n (11-bit ID), 54 + 8n (29-bit).
uint16_t stuffable_bits(bool extended, uint8_t dlc);

/// Largest number of stuff bits the chosen convention allows.
uint16_t worst_stuff_bits(bool extended, uint8_t dlc, WorstCase convention);

/// frame_bits_unstuffed + worst_stuff_bits: the transmission time C in bits.
uint16_t frame_bits_worst(bool extended, uint8_t dlc, WorstCase convention);

/// The exact make-up of one concrete frame on the wire.
struct ExactFrameBits {
  uint16_t total_bits;  ///< SOF .. IFS including stuff bits
  uint16_t stuff_bits;  ///< stuff bits inserted between SOF and the CRC end
  uint16_t crc15;       ///< the frame's CRC sequence (polynomial 0x4599)
};

/// Exact length of `frame` (data or remote frame, 11- or 29-bit ID). The ID is
/// masked to its width; data bytes beyond dlc_bytes(dlc) are not read.
ExactFrameBits frame_bits_exact(const CanFrame& frame);

/// CAN CRC-15 register update by one bit (ISO 11898-1): the building block of
/// frame_bits_exact, exposed for tests against published check values.
uint16_t crc15_update(uint16_t crc, bool bit);

}  // namespace timing
}  // namespace mb2co
