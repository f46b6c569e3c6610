// Worst-case response-time analysis of CAN messages under fixed priorities
// and non-preemptive transmission (seed 000 §2.12-2.13; Davis, Burns, Bril,
// Lukkien 2007). Works in any integer time unit the caller chooses (the CLI
// uses the ticks of time_base.h); every ceiling is an integer division.
//
// Input: an array in priority order, index 0 the highest priority (lowest
// CAN identifier). The analysis reads it only; results go into a caller-owned
// array of the same length. Cost per message: O(i) per iteration of each
// fixed-point equation, for every instance in its busy period.
#pragma once
#include <stddef.h>
#include <stdint.h>

namespace mb2co {
namespace timing {

/// One message. Invariant checked by analyse(): 0 < c, t, d ≤ kMaxValue,
/// j ≤ kMaxValue.
struct RtaMessage {
  uint64_t c;  ///< worst-case transmission time C (whole frame incl. IFS)
  uint64_t t;  ///< period, or minimum inter-arrival time of a sporadic message
  uint64_t d;  ///< deadline, from the event that releases the message
  uint64_t j;  ///< queuing jitter: how late after the event it may be queued
};

/// Largest accepted time value: 2^52 (71 min in ticks at 1 Mbit/s).
constexpr uint64_t kMaxValue = uint64_t{1} << 52;
/// A busy period longer than this is reported as kHorizon (2^60 ticks:
/// 13 days at 1 Mbit/s), which also keeps every sum far from overflow.
constexpr uint64_t kMaxBusyPeriod = uint64_t{1} << 60;
/// More instances than this in one busy period are reported as kHorizon.
constexpr uint64_t kMaxInstances = uint64_t{1} << 20;

/// Whether a fixed-point iteration ended.
enum class Bound : uint8_t {
  kBounded,      ///< converged: the value is valid
  kUtilisation,  ///< the utilisation at this level reaches 1: no bound exists
  kHorizon,      ///< gave up at kMaxBusyPeriod or kMaxInstances
};

struct RtaResult {
  uint64_t blocking;           ///< B: longest C among lower priorities
  Bound first;                 ///< outcome of the first attempt (§2.12)
  uint64_t r_first;            ///< first attempt: J + w + C, instance 0 only
  Bound revised;               ///< outcome of the revised analysis (§2.13)
  uint64_t busy;               ///< L: level-i busy period
  uint64_t instances;          ///< Q = ceil((L + J)/T) instances in it
  uint64_t critical_instance;  ///< the q whose response time is R
  uint64_t r;                  ///< R = max over q of R_q
  bool schedulable;            ///< revised bounded and R ≤ D
  bool first_optimistic;       ///< first attempt gave less than the truth
};

enum class RtaStatus : uint8_t {
  kOk,
  kBadMessage,  ///< some c, t or d is 0, or a value exceeds kMaxValue
};

/// Analyses every message of `set` (priority order) with bit time `tau_bit`
/// (> 0 in the same unit; it is how late a higher-priority message may be
/// queued and still win arbitration). Fills results[0..count).
/// On kBadMessage, *bad_index names the first offending message.
RtaStatus analyse(const RtaMessage* set, size_t count, uint64_t tau_bit, RtaResult* results,
                  size_t* bad_index);

// The pieces, exposed so that tests and reports can show each equation.

/// B_i = max C_k over k > i (0 for the lowest priority).
uint64_t blocking_time(const RtaMessage* set, size_t count, size_t i);

/// Level-i busy period, eq. 6.7 with jitter:
/// L = B + Σ_{k ≤ i} ceil((L + J_k)/T_k) C_k, from L(0) = B + Σ_{k ≤ i} C_k.
/// Only valid when the level-i utilisation is below 1 (checked by analyse).
uint64_t busy_period(const RtaMessage* set, size_t i, uint64_t blocking, Bound* outcome);

/// Queuing delay of instance q, eq. 6.10 with jitter:
/// w = B + q C_i + Σ_{k < i} ceil((w + J_k + τ_bit)/T_k) C_k, from w_start.
/// With q = 0 this is also the first attempt's W (seed eq. 6.5 plus J, τ_bit).
uint64_t queuing_delay(const RtaMessage* set, size_t i, uint64_t tau_bit, uint64_t blocking, uint64_t q,
                       uint64_t w_start, Bound* outcome);

}  // namespace timing
}  // namespace mb2co
