#include "timing/sync_latency.h"

#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

constexpr uint64_t kNsPerUs = 1000;
constexpr uint16_t kIfsBits = 3;  ///< a receiver has the frame at the end of EOF

uint64_t us(uint32_t value) {
  return value * kNsPerUs;
}

uint64_t frame_worst_ns(uint8_t dlc, const SyncParams& p) {
  const uint16_t bits = static_cast<uint16_t>(frame_bits_worst(false, dlc, p.convention) - kIfsBits);
  return bits_to_ns_ceil(bits, p.bitrate_bps);
}

// From the SYNC's reception at the PDO node to the PDO's reception at the
// SYNC producer: the PDO node's pass, the PDO's wait for the bus, the PDO.
void response(const SyncParams& p, LatencyBound& b) {
  add_latency_term(b, "sync_pass", us(p.pass_min_us), us(p.fw_loop_us));
  add_latency_term(b, "pdo_queueing", 0, p.pdo_queueing_worst_ns);
  add_latency_term(b, "pdo_frame", pdo_frame_best_ns(p), pdo_frame_worst_ns(p));
}

}  // namespace

bool sync_params_valid(const SyncParams& p) {
  return bitrate_valid(p.bitrate_bps) && p.sync_period_us > 0 && p.transmission_type >= 1 &&
         p.transmission_type <= 240 && p.sync_dlc <= 1 && p.pdo_dlc <= 8;
}

uint64_t sync_frame_best_ns(const SyncParams& p) {
  return can_hop_best_ns(false, p.sync_dlc, p.bitrate_bps);
}

uint64_t sync_frame_worst_ns(const SyncParams& p) {
  return frame_worst_ns(p.sync_dlc, p);
}

uint64_t pdo_frame_best_ns(const SyncParams& p) {
  return can_hop_best_ns(false, p.pdo_dlc, p.bitrate_bps);
}

uint64_t pdo_frame_worst_ns(const SyncParams& p) {
  return frame_worst_ns(p.pdo_dlc, p);
}

LatencyBound sync_round_trip_bound(const SyncParams& p) {
  LatencyBound b = {};
  add_latency_term(b, "sync_frame", sync_frame_best_ns(p), sync_frame_worst_ns(p));
  response(p, b);
  return b;
}

LatencyBound sync_response_bound(const SyncParams& p) {
  LatencyBound b = {};
  add_latency_term(b, "debounce", us(p.debounce_us), us(p.debounce_us));
  add_latency_term(b, "input_pass", 0, us(p.fw_loop_us));
  // SYNC k reaches the PDO node at k·period + d_k with d_k between the bare
  // frame and jitter + queueing + the stuffed frame; the period does not
  // drift, so n SYNCs after any instant are at most n·period + the spread
  // of d away. Best: the n-th SYNC arrives just after the value.
  const uint64_t spread =
      us(p.sync_jitter_us) + p.sync_queueing_worst_ns + sync_frame_worst_ns(p) - sync_frame_best_ns(p);
  add_latency_term(b, "sync_wait", 0, uint64_t{p.transmission_type} * us(p.sync_period_us) + spread);
  response(p, b);
  add_latency_term(b, "rpdo_pass", us(p.pass_min_us), us(p.fw_loop_us));
  return b;
}

bool sync_window_met(const SyncParams& p) {
  return p.sync_window_us == 0 || sync_round_trip_bound(p).worst_ns <= us(p.sync_window_us);
}

}  // namespace timing
}  // namespace mb2co
