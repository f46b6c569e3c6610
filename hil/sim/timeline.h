// What a scenario records while it runs: the timeline of RUN changes and
// button presses, and its progress. The vocabulary of the scenario runners'
// results (scenarios.h) and of the parts they are built from
// (scenario_parts.h), so neither includes the other's level.
#pragma once
#include <stdint.h>

#include <functional>

#include "sim/event_queue.h"

namespace mb2co {
namespace sim {

/// Progress of a long run, 0..1 (called now and then).
using Progress = std::function<void(double fraction)>;

/// A RUN state change of a station's gateway (2100h/2) or a STOP2 press.
struct TimelineEvent {
  SimNs t_ns;
  int station;
  enum Kind : uint8_t { kRun, kStop, kStop2Press, kStartPress, kUnknown, kAlive } kind;
};

}  // namespace sim
}  // namespace mb2co
