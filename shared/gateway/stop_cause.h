// Why a station stopped: the one list of stop causes on the line, with the
// values 2100h/4 holds. The firmware latches and reports these; the PC's
// controller counts its stops by plant::StopCause, which maps onto this list
// (plant::reported_cause). No includes: the PC side uses it without the core.
#pragma once
#include <stdint.h>

namespace mb2co {
namespace gateway {

/// The cause of the latched stop, as 2100h/4 reads: these values are on the
/// wire (docs/register-map.md), so they never change.
enum StopCause : uint8_t {
  kCauseNone = 0,           ///< running, or stopped by the PC's RUN command 0
  kCauseStopButton = 1,     ///< STOP pressed on this station's panel
  kCauseStop2Here = 2,      ///< STOP2 pressed on this station's panel
  kCauseStop2Previous = 3,  ///< a new STOP2 event of the previous station
  kCausePcSilent = 4,       ///< no Modbus request for the watchdog time (2000h/9)
};

}  // namespace gateway
}  // namespace mb2co
