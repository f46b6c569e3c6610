// The host's wall clock as CANopen's TIME_OF_DAY (mb2co-master time). UTC:
// CiA 301 names no time zone, and a network whose nodes compare stamps
// needs one scale everywhere (CANopenNode's examples send UTC too).
#pragma once
#include <stdint.h>

#include <string>

#include "canopen/time_of_day.h"

namespace mb2co {
namespace master {

/// 1984-01-01T00:00:00Z, TIME_OF_DAY's day 0, in ms since the Unix epoch.
const int64_t kCanopenEpochUnixMs = 441763200000LL;

/// False when `unix_ms` lies outside what TIME_OF_DAY can carry (before
/// 1984-01-01 or after day 65,535, in 2163); else *out is that instant.
bool time_of_day_of_unix_ms(int64_t unix_ms, canopen::TimeOfDay* out);

/// "2026-11-29T15:04:05.123Z": the instant `t` stands for (ISO 8601, UTC).
std::string utc_text(const canopen::TimeOfDay& t);

/// The host's wall clock now, ms since the Unix epoch (CLOCK_REALTIME).
int64_t wall_clock_unix_ms();

}  // namespace master
}  // namespace mb2co
