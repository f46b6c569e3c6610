#include "timing/line_config.h"

#include <string.h>

#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

// "<prefix><number>" without printf (not available on every target).
void numbered_name(MessageSpec& m, const char* prefix, unsigned number) {
  char digits[4];
  size_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + number % 10u);
    number /= 10u;
  } while (number != 0 && n < sizeof digits);
  set_name(m, prefix);
  size_t len = strlen(m.name);
  while (n > 0 && len + 1 < kNameCapacity) m.name[len++] = digits[--n];
  m.name[len] = '\0';
}

MessageSpec make(uint32_t id, uint8_t dlc, uint32_t period_us, uint32_t deadline_us, uint32_t jitter_us) {
  MessageSpec m{};
  m.id = id;
  m.dlc = dlc;
  m.period_us = period_us;
  m.deadline_us = deadline_us != 0 ? deadline_us : period_us;
  m.jitter_us = jitter_us;
  return m;
}

LineStatus check(const LineCanConfig& cfg) {
  if (cfg.stations == 0 || cfg.stations > kMaxStations) return LineStatus::kStations;
  if (!bitrate_valid(cfg.bitrate_bps)) return LineStatus::kBitrate;
  if (cfg.tpdo1) {
    if (cfg.tpdo1_inhibit_100us == 0) return LineStatus::kNoInterArrival;
    if (cfg.tpdo1_event_timer_ms != 0 && uint32_t{cfg.tpdo1_event_timer_ms} * 10u < cfg.tpdo1_inhibit_100us) {
      return LineStatus::kEventTimer;
    }
    if (cfg.tpdo1_dlc > 8) return LineStatus::kDlc;
  }
  if (cfg.sync_tpdos > kMaxSyncTpdos || (cfg.sync_tpdos != 0 && cfg.sync_period_us == 0)) {
    return LineStatus::kSyncTpdos;
  }
  if (cfg.sync_tpdos != 0) {
    if (cfg.sync_transmission_type == 0 || cfg.sync_transmission_type > 240) {
      return LineStatus::kTransmissionType;
    }
    if (cfg.sync_tpdo_dlc > 8) return LineStatus::kDlc;
    if (uint64_t{cfg.sync_period_us} * cfg.sync_transmission_type > 0xFFFFFFFFu) {
      return LineStatus::kTransmissionType;  // period beyond the 32-bit µs range
    }
  }
  return LineStatus::kOk;
}

}  // namespace

size_t line_message_count(const LineCanConfig& cfg) {
  const size_t per_station = (cfg.tpdo1 ? 1u : 0u) + (cfg.heartbeat_ms != 0 ? 1u : 0u) +
                             (cfg.sync_period_us != 0 ? cfg.sync_tpdos : 0u);
  return (cfg.sync_period_us != 0 ? 1u : 0u) + cfg.stations * per_station;
}

LineStatus build_line_messages(const LineCanConfig& cfg, MessageSpec* out, size_t capacity, size_t* count) {
  *count = 0;
  const LineStatus status = check(cfg);
  if (status != LineStatus::kOk) return status;
  if (line_message_count(cfg) > capacity) return LineStatus::kCapacity;

  size_t n = 0;
  const uint32_t jitter = cfg.queue_jitter_us;
  if (cfg.sync_period_us != 0) {
    out[n] = make(kSyncCobId, 0, cfg.sync_period_us, 0, jitter);
    set_name(out[n++], "SYNC");
  }
  for (unsigned node = 1; node <= cfg.stations; ++node) {
    if (cfg.tpdo1) {
      const uint32_t inhibit_us = uint32_t{cfg.tpdo1_inhibit_100us} * 100u;
      out[n] = make(kTpdo1CobBase + node, cfg.tpdo1_dlc, inhibit_us, cfg.tpdo1_deadline_us, jitter);
      numbered_name(out[n++], "TPDO1.", node);
    }
    if (cfg.sync_period_us != 0) {
      for (unsigned k = 0; k < cfg.sync_tpdos; ++k) {
        const uint32_t period = cfg.sync_period_us * cfg.sync_transmission_type;
        out[n] = make(kTpdo1CobBase + (k + 1u) * kTpdoCobStep + node, cfg.sync_tpdo_dlc, period, 0, jitter);
        char prefix[] = "TPDOx.";
        prefix[4] = static_cast<char>('2' + k);
        numbered_name(out[n++], prefix, node);
      }
    }
    if (cfg.heartbeat_ms != 0) {
      out[n] = make(kHeartbeatCobBase + node, 1, uint32_t{cfg.heartbeat_ms} * 1000u, 0, jitter);
      numbered_name(out[n++], "HB.", node);
    }
  }
  sort_by_priority(out, n);
  *count = n;
  return LineStatus::kOk;
}

}  // namespace timing
}  // namespace mb2co
