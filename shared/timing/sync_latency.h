// Bounds of the week-13 SYNC measurements (seed 000 §5), best and worst case,
// as named terms like latency.h (docs/timing.md lists them):
//   §5.2 round trip: from the start of the SYNC frame on the bus ("immediately
//        before starting to send the synch message") to the end of the
//        response PDO's reception at the SYNC producer;
//   §5.3 response:   joystick (a button) on the Arduino sending the PDOs to
//        the LED on the Arduino sending the SYNC messages, the PDO sent every
//        n-th SYNC (transmission type n, 1..240).
//
// Model (one assumption per term): a received frame waits at most one
// firmware loop pass to be noticed, and what it causes leaves at the end of
// the pass that handles it (pass_min_us .. fw_loop_us after its reception);
// the SYNC producer queues a SYNC at most sync_jitter_us after its period
// elapsed and its period does not drift (1006h counts from the previous
// period's start, canopen/sync.h); the receiving node acts on an RPDO at
// once (transmission type 254/255). Times in ns; lower bounds round down,
// upper bounds up.
#pragma once
#include <stdint.h>

#include "timing/can_bits.h"
#include "timing/latency.h"

namespace mb2co {
namespace timing {

struct SyncParams {
  uint32_t bitrate_bps = 500000;
  WorstCase convention = WorstCase::kDavis;  ///< worst-case bit stuffing of both frames
  // --- the synch message (1005h, 1006h, 1007h, 1019h)
  uint32_t sync_period_us = 10000;      ///< 1006h communication cycle period (> 0)
  uint32_t sync_window_us = 0;          ///< 1007h synchronous window length; 0 = none
  uint32_t sync_jitter_us = 0;          ///< how late after its period the producer queues the SYNC
  uint8_t sync_dlc = 0;                 ///< 0, or 1 with a SYNC counter (1019h > 0)
  uint64_t sync_queueing_worst_ns = 0;  ///< SYNC's wait on the bus (blocking by a frame in progress)
  // --- the response PDO (1800h+k, 1A00h+k)
  uint8_t transmission_type = 1;  ///< n: sent at every n-th SYNC, 1..240
  uint8_t pdo_dlc = 1;            ///< data bytes of the response PDO
  /// Queueing of the PDO behind higher-priority frames and a lower-priority
  /// one in progress: R − C of the response-time analysis (rta.h).
  uint64_t pdo_queueing_worst_ns = 0;
  // --- firmware (both Arduinos alike)
  uint32_t pass_min_us = 0;    ///< shortest time from a frame's reception to the end of the pass handling it
  uint32_t fw_loop_us = 1000;  ///< longest such time (loop pass in progress + the handling pass)
  uint32_t debounce_us = 20000;  ///< a press counts after being stable this long (§5.3 only)
};

/// Requires 0 < transmission_type ≤ 240, sync_period_us > 0, a valid bit
/// rate (time_base.h), sync_dlc ≤ 1, pdo_dlc ≤ 8.
bool sync_params_valid(const SyncParams& p);

/// SYNC frame on the bus until its reception (end of EOF): best without stuff
/// bits, worst with the convention's stuffing (rounded up).
uint64_t sync_frame_best_ns(const SyncParams& p);
uint64_t sync_frame_worst_ns(const SyncParams& p);
/// The response PDO from its first bit to its reception, likewise.
uint64_t pdo_frame_best_ns(const SyncParams& p);
uint64_t pdo_frame_worst_ns(const SyncParams& p);

/// §5.2: sync_frame + sync_pass (the PDO node's processing) + pdo_queueing
/// + pdo_frame. The measurement starts at the SYNC's first bit, so the SYNC's
/// own queueing and the producer's jitter are not in it.
LatencyBound sync_round_trip_bound(const SyncParams& p);

/// §5.3: debounce + input_pass + sync_wait (the value in the OD until the
/// n-th SYNC's reception: best 0, worst n · period + the spread of the SYNC's
/// arrival: producer jitter, SYNC queueing and stuffing) + sync_pass +
/// pdo_queueing + pdo_frame + rpdo_pass (the LED node's pass).
LatencyBound sync_response_bound(const SyncParams& p);

/// True when the PDO always leaves inside the synchronous window (1007h)
/// after the SYNC's reception, or when there is no window.
bool sync_window_met(const SyncParams& p);

}  // namespace timing
}  // namespace mb2co
