// The line's values as they are on the wire (docs/register-map.md): button
// and LED bits, a neighbour's status. No includes: the PC's station cycle
// (shared/plant) decodes registers with them without the core.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace gateway {

enum Button : uint8_t { kStart = 0x01, kStop = 0x02, kStop2 = 0x04 };
enum Led : uint8_t { kLedRunSelf = 0x01, kLedRunPrev = 0x02, kLedRunNext = 0x04, kLedLab = 0x08 };
/// 2110h/3, 2120h/3: a neighbour's status (low bits) and a flag.
enum NeighbourStatus : uint8_t {
  kNeighbourUnknown = 0,  ///< no heartbeat (lost, or not yet heard): never "running"
  kNeighbourAlive = 1,
  kNeighbourNone = 2,  ///< end of a chain: no such station
  /// Flag beside the status: no TPDO1 of this neighbour since this gateway's
  /// reset, so its RUN state and STOP2 counter (2110h/1-2, 2120h/1-2) are
  /// placeholders (0), not values it sent. Cleared by its first TPDO1; a
  /// lost heartbeat does not set it again (the values then are the last it
  /// sent). A PC counts no STOP2 events from a counter read with it set.
  kNeighbourNotHeard = 0x80,
};
}  // namespace gateway
}  // namespace mb2co
