// The operator of the latency labs (seed 000 §5.3, §11): presses a button
// at random phases and measures the time from the contact closing to the
// lab LED changing. Internal to hil/sim's scenarios.
#pragma once
#include <stdint.h>

#include <vector>

#include "sim/line.h"
#include "sim/rng.h"
#include "sim/scenarios.h"

namespace mb2co {
namespace sim {

struct PressRun {
  std::vector<SimNs> samples_ns;  ///< press → lab LED on, per press
  uint32_t lost = 0;              ///< presses whose LED never came within 1 s
};

/// From 1 s of line time on: waits 20–60 ms, presses START on
/// `button_station`, waits for the lab LED of `led_station` (at most 1 s),
/// holds 20–50 ms, releases, waits for the LED to go off (at most 1 s); until
/// `presses` presses are done. Takes over line.on_leds. Draws from `rng` only.
/// Its pending callbacks refer to its own state: the line must not run on
/// after it returns.
PressRun run_presses(Line& line, int button_station, int led_station, uint32_t presses, Rng& rng,
                     const Progress& progress);

/// min, mean, p99 (nearest rank) and max of `samples` (all 0 when empty).
struct SampleStats {
  SimNs min_ns = 0, max_ns = 0, p99_ns = 0;
  double mean_ns = 0;
};
SampleStats sample_stats(const std::vector<SimNs>& samples);

/// Fills r's statistics, counts the samples outside r.bound and sets r.ok:
/// a bound exists, there are samples and every one lies inside it.
void judge_latency(LatencyResult& r);

}  // namespace sim
}  // namespace mb2co
