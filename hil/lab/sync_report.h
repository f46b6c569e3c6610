// Report sections of the week-13 SYNC labs (seed 000 §5.2, §5.3) and of
// §11's simpler alternative (hil/sim/sync_scenarios.h). Deterministic text.
#pragma once
#include <string>
#include <vector>

#include "sim/sync_scenarios.h"

namespace mb2co {
namespace lab {

/// §5.2 per bit rate: n, min, mean, max (µs), the bound, max/worst, the
/// bound's terms, the verdict naming its criterion.
std::string sync_roundtrip_section(const std::vector<sim::SyncResult>& results);
/// §5.3 likewise in ms.
std::string sync_latency_section(const std::vector<sim::SyncResult>& results);
/// One row per measurement: bitrate_kbit,n,value_ns,best_ns,worst_ns,inside.
std::string sync_csv(const std::vector<sim::SyncResult>& results);

/// §11: the two PC-controlled paths and the Arduino-controlled one per bit rate.
std::string alternative_section(const std::vector<sim::AlternativeResult>& results);

/// Histogram of one bit rate's §5.2 round trips (us) or §5.3 presses (ms),
/// the bound drawn (histogram_svg.h).
std::string sync_svg(const sim::SyncResult& r, bool roundtrip);
/// §11 at one bit rate: the three paths as three panels, each bound drawn.
std::string alternative_svg(const sim::AlternativeResult& r);

}  // namespace lab
}  // namespace mb2co
