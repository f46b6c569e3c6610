// A CAN message set as a user states it (identifier, DLC, period, deadline,
// jitter) and its translation into the integer analysis of rta.h at one bit
// rate. Also the bus-load figures of seed 000 §2.11. The caller owns arrays.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "timing/can_bits.h"
#include "timing/rta.h"
#include "timing/utilisation.h"

namespace mb2co {
namespace timing {

constexpr size_t kNameCapacity = 24;  ///< bytes of MessageSpec::name, NUL included

/// One message. Times in µs. Invariant (check_spec): id fits its width,
/// dlc ≤ 8, period and deadline > 0.
struct MessageSpec {
  char name[kNameCapacity];  ///< NUL-terminated label
  uint32_t id;               ///< CAN identifier (COB-ID), 11 or 29 bits
  bool extended;             ///< 29-bit identifier
  uint8_t dlc;               ///< data bytes 0..8
  uint32_t period_us;        ///< period, or minimum inter-arrival time
  uint32_t deadline_us;      ///< relative deadline (often = period)
  uint32_t jitter_us;        ///< queuing jitter
  uint64_t c_ns;             ///< > 0: given transmission time (ns), overrides bits
  uint16_t bits;             ///< > 0: given frame length, overrides dlc
};

enum class SpecError : uint8_t {
  kOk,
  kIdRange,       ///< id beyond 0x7FF (standard) or 0x1FFFFFFF (extended)
  kDlcRange,      ///< dlc > 8
  kPeriodZero,    ///< period_us == 0
  kDeadlineZero,  ///< deadline_us == 0
};

SpecError check_spec(const MessageSpec& m);

/// CAN arbitration order: a lower key wins. A standard frame beats an
/// extended one with the same 11 base bits (its RTR bit meets the SRR bit).
uint32_t arbitration_key(uint32_t id, bool extended);

/// Worst-case transmission time C in ticks (time_base.h) at `bitrate_bps`:
/// c_ns if given (rounded up to a whole tick: exact at every bit rate that
/// is a multiple of 1 kbit/s), else bits if given, else frame_bits_worst(dlc).
uint64_t transmission_ticks(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention);

/// Bus time of m in whole bit times (C / τ_bit, rounded up).
uint64_t message_bits(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention);

/// The analysis input for m (ticks).
RtaMessage to_rta(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention);

/// Runs analyse() on a set already in priority order at `bitrate_bps`, with
/// τ_bit = one bit time. rta[] and results[] are caller-owned, count long.
RtaStatus analyse_set(const MessageSpec* sorted, size_t count, uint32_t bitrate_bps, WorstCase convention,
                      RtaMessage* rta, RtaResult* results, size_t* bad_index);

/// Stable sort into priority order (arbitration_key ascending). Insertion
/// sort: no heap, fine for a few thousand messages.
void sort_by_priority(MessageSpec* set, size_t count);

/// In a sorted set, the first two messages with the same identifier (CAN
/// needs unique identifiers). False when all are unique.
bool find_duplicate_id(const MessageSpec* sorted, size_t count, size_t* first, size_t* second);

/// Σ C_k / T_k at `bitrate_bps`: the bus utilisation (load / bit rate).
Utilisation set_utilisation(const MessageSpec* set, size_t count, uint32_t bitrate_bps, WorstCase convention);

/// Σ C_k / T_k in bit/s: the bus load of seed 000 §2.11 (65,000 bit/s for
/// its four-PDO set), as exact bounds. A c_ns override counts as the bits it
/// lasts at `bitrate_bps`.
Utilisation bus_load_bps(const MessageSpec* set, size_t count, uint32_t bitrate_bps, WorstCase convention);

/// Bits released in a window of `window_us` at worst: Σ bits_k ·
/// ceil(window/T_k). For a SYNC window this is seed 000 §2.11's test: the set
/// fits when the result ≤ window_us · bitrate / 10^6.
uint64_t window_bits(const MessageSpec* set, size_t count, uint32_t window_us, uint32_t bitrate_bps,
                     WorstCase convention);

/// Bits a bus carries in `window_us`: window_us · bitrate / 10^6, rounded down.
uint64_t window_capacity_bits(uint32_t window_us, uint32_t bitrate_bps);

/// Copies `text` into m.name, truncated to kNameCapacity - 1 bytes.
void set_name(MessageSpec& m, const char* text);

}  // namespace timing
}  // namespace mb2co
