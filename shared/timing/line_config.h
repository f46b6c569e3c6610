// The CAN traffic of the production line (DESIGN §6) as a message set for the
// analysis: a plain description that the line application will later fill
// from its Object Dictionary (1005h/1006h SYNC, 1017h heartbeat, 1800h+
// TPDO communication parameters). Until then the defaults below describe the
// RUN/STOP2 line as designed.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "timing/message_set.h"

namespace mb2co {
namespace timing {

/// CiA 301 default COB-IDs used by the line (+ node ID where per node).
constexpr uint32_t kSyncCobId = 0x80;
constexpr uint32_t kTpdo1CobBase = 0x180;
constexpr uint32_t kTpdoCobStep = 0x100;  ///< TPDO2 0x280, TPDO3 0x380, TPDO4 0x480
constexpr uint32_t kHeartbeatCobBase = 0x700;

/// Most stations on one CANopen network (node IDs 1..127).
constexpr uint8_t kMaxStations = 127;
/// Synchronous TPDOs per station beyond TPDO1: TPDO2..TPDO4.
constexpr uint8_t kMaxSyncTpdos = 3;

struct LineCanConfig {
  /// N stations, node IDs 1..N (3-4 in class).
  uint8_t stations = 3;
  /// CAN bit rate in bit/s (CiA 301: 10k .. 1M).
  uint32_t bitrate_bps = 125000;

  /// TPDO1 of every station: {RUN state, STOP2 counter}, event-driven
  /// (transmission type 254/255), COB-ID 0x180 + node ID.
  bool tpdo1 = true;
  /// TPDO1 data bytes (RUN state 1 + STOP2 counter 1).
  uint8_t tpdo1_dlc = 3;  ///< the gateway: RUN state (1 byte) + STOP2 counter (2 bytes)
  /// 1800h sub3, inhibit time in 100 µs units: 100 = 10 ms. Also the minimum
  /// inter-arrival time T of the event-driven PDO (seed 000 §2.11); must be
  /// > 0, else the PDO has no bounded rate.
  uint16_t tpdo1_inhibit_100us = 100;
  /// 1800h sub5, event timer in ms (0 = off): a refresh when nothing changed.
  /// It never makes the PDO faster than the inhibit time, so T stays the
  /// inhibit time; must be 0 or ≥ the inhibit time.
  uint16_t tpdo1_event_timer_ms = 100;
  /// Deadline of TPDO1 in µs; 0 = equal to its inter-arrival time.
  uint32_t tpdo1_deadline_us = 0;

  /// 1017h producer heartbeat time in ms, COB-ID 0x700 + node ID, 1 byte;
  /// 0 = no heartbeat.
  uint16_t heartbeat_ms = 100;

  /// 1006h communication cycle period in µs of the SYNC producer (COB-ID 80h,
  /// 0 bytes); 0 = no SYNC on the line.
  uint32_t sync_period_us = 0;
  /// Synchronous TPDOs per station (TPDO2.. at 0x280/0x380/0x480 + node ID),
  /// 0..kMaxSyncTpdos; only with a SYNC period.
  uint8_t sync_tpdos = 0;
  /// Data bytes of each synchronous TPDO.
  uint8_t sync_tpdo_dlc = 8;
  /// Transmission type 1..240: sent on every n-th SYNC, so T = n · SYNC period.
  uint8_t sync_transmission_type = 1;

  /// Queuing jitter of every message in µs (e.g. the firmware loop that
  /// notices the event and queues the frame).
  uint32_t queue_jitter_us = 0;
};

enum class LineStatus : uint8_t {
  kOk,
  kStations,          ///< stations 0 or > 127
  kBitrate,           ///< bit rate 0 or > 1 Mbit/s
  kNoInterArrival,    ///< event-driven TPDO1 with inhibit time 0
  kEventTimer,        ///< event timer shorter than the inhibit time
  kSyncTpdos,         ///< more than 3, or synchronous TPDOs without a SYNC
  kTransmissionType,  ///< outside 1..240, or type · SYNC period beyond 2^32 µs
  kDlc,               ///< a DLC above 8
  kCapacity,          ///< out[] too small: line_message_count() entries needed
};

/// How many messages build_line_messages() produces for cfg.
size_t line_message_count(const LineCanConfig& cfg);

/// Writes the line's message set into out[0..*count) in priority order:
/// SYNC "SYNC", then per station "TPDO1.<id>", "TPDO<k>.<id>" (synchronous)
/// and "HB.<id>". Deadlines equal periods unless stated.
LineStatus build_line_messages(const LineCanConfig& cfg, MessageSpec* out, size_t capacity, size_t* count);

}  // namespace timing
}  // namespace mb2co
