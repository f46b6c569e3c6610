#include "timing/message_set.h"

#include <string.h>

#include "timing/time_base.h"

namespace mb2co {
namespace timing {

SpecError check_spec(const MessageSpec& m) {
  if (m.id > (m.extended ? 0x1FFFFFFFu : 0x7FFu)) return SpecError::kIdRange;
  if (m.dlc > 8) return SpecError::kDlcRange;
  if (m.period_us == 0) return SpecError::kPeriodZero;
  if (m.deadline_us == 0) return SpecError::kDeadlineZero;
  return SpecError::kOk;
}

uint32_t arbitration_key(uint32_t id, bool extended) {
  // Bits in the order they meet on the wire: 11 base bits, then RTR/SRR
  // (dominant for a standard data frame, recessive SRR for extended), then
  // the 18 extension bits.
  if (!extended) return (id & 0x7FFu) << 19;
  const uint32_t base = (id >> 18) & 0x7FFu;
  return (base << 19) | (uint32_t{1} << 18) | (id & 0x3FFFFu);
}

uint64_t transmission_ticks(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention) {
  if (m.c_ns != 0) return (m.c_ns * bitrate_bps + 999u) / 1000u;  // 1 ns = bitrate / 1000 ticks
  const uint16_t bits = m.bits != 0 ? m.bits : frame_bits_worst(m.extended, m.dlc, convention);
  return bits_to_ticks(bits);
}

uint64_t message_bits(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention) {
  return ticks_to_bits_ceil(transmission_ticks(m, bitrate_bps, convention));
}

RtaMessage to_rta(const MessageSpec& m, uint32_t bitrate_bps, WorstCase convention) {
  RtaMessage r;
  r.c = transmission_ticks(m, bitrate_bps, convention);
  r.t = us_to_ticks(m.period_us, bitrate_bps);
  r.d = us_to_ticks(m.deadline_us, bitrate_bps);
  r.j = us_to_ticks(m.jitter_us, bitrate_bps);
  return r;
}

RtaStatus analyse_set(const MessageSpec* sorted, size_t count, uint32_t bitrate_bps, WorstCase convention,
                      RtaMessage* rta, RtaResult* results, size_t* bad_index) {
  for (size_t i = 0; i < count; ++i) rta[i] = to_rta(sorted[i], bitrate_bps, convention);
  return analyse(rta, count, bits_to_ticks(1), results, bad_index);
}

void sort_by_priority(MessageSpec* set, size_t count) {
  for (size_t i = 1; i < count; ++i) {
    const MessageSpec moving = set[i];
    const uint32_t key = arbitration_key(moving.id, moving.extended);
    size_t j = i;
    while (j > 0 && arbitration_key(set[j - 1].id, set[j - 1].extended) > key) {
      set[j] = set[j - 1];
      --j;
    }
    set[j] = moving;
  }
}

bool find_duplicate_id(const MessageSpec* sorted, size_t count, size_t* first, size_t* second) {
  for (size_t i = 1; i < count; ++i) {
    if (arbitration_key(sorted[i - 1].id, sorted[i - 1].extended) ==
        arbitration_key(sorted[i].id, sorted[i].extended)) {
      *first = i - 1;
      *second = i;
      return true;
    }
  }
  return false;
}

Utilisation set_utilisation(const MessageSpec* set, size_t count, uint32_t bitrate_bps,
                            WorstCase convention) {
  Utilisation u;
  for (size_t i = 0; i < count; ++i) {
    u.add(transmission_ticks(set[i], bitrate_bps, convention), us_to_ticks(set[i].period_us, bitrate_bps));
  }
  return u;
}

Utilisation bus_load_bps(const MessageSpec* set, size_t count, uint32_t bitrate_bps, WorstCase convention) {
  // C in ticks is bits · 10^6; over T in µs that is bits per second.
  Utilisation load;
  for (size_t i = 0; i < count; ++i) {
    load.add(transmission_ticks(set[i], bitrate_bps, convention), set[i].period_us);
  }
  return load;
}

uint64_t window_bits(const MessageSpec* set, size_t count, uint32_t window_us, uint32_t bitrate_bps,
                     WorstCase convention) {
  uint64_t bits = 0;
  for (size_t i = 0; i < count; ++i) {
    const uint64_t releases = (uint64_t{window_us} + set[i].period_us - 1u) / set[i].period_us;
    bits += releases * message_bits(set[i], bitrate_bps, convention);
  }
  return bits;
}

uint64_t window_capacity_bits(uint32_t window_us, uint32_t bitrate_bps) {
  return uint64_t{window_us} * bitrate_bps / 1000000u;
}

void set_name(MessageSpec& m, const char* text) {
  strncpy(m.name, text, kNameCapacity - 1);
  m.name[kNameCapacity - 1] = '\0';
}

}  // namespace timing
}  // namespace mb2co
