// The week-13 SYNC labs (seed 000 §5.2, §5.3) and §11's simpler alternative
// on the simulated line, each against its bound from shared/timing. Station
// 1 (A) is the Arduino sending the synch messages (1005h bit 30, 1006h) and
// has the LED; station 2 (B) answers with a synchronous PDO: its TPDO2
// (buttons, 6000h/1) gets transmission type n (1801h/2), as a student
// commissions it by SDO. The other stations of the line are there as they
// are (their heartbeats and TPDO1s are the traffic a PDO queues behind).
//   sync-roundtrip  §5.2: SYNC's first bit → B's PDO received at A
//   sync-latency    §5.3: B's button (joystick) → A's LED, B's PDO at every
//                   n-th SYNC, A's RPDO4 maps it onto 6200h/1 (lab LED)
//   alternative     §11: button and LED on B, the control process on A
//                   (A's RPDO4 writes B's button into A's LED object, which
//                   A's TPDO3 sends to B's RPDO4), next to the two
//                   PC-controlled paths of the latency lab
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "sim/lab_bound.h"
#include "sim/line.h"
#include "sim/press_loop.h"
#include "sim/scenarios.h"
#include "timing/sync_latency.h"

namespace mb2co {
namespace sim {

struct SyncLabConfig {
  uint32_t bitrate_kbit = 500;
  uint32_t sync_period_us = 10000;  ///< 1006h of the producer
  uint8_t transmission_type = 1;    ///< 1801h/2 of B's TPDO2, 1..240
  /// 0: the bound uses the configured period; else it assumes this one (a
  /// deliberately wrong bound shows that the check is real).
  uint32_t bound_sync_period_us = 0;
};

struct SyncResult {
  SyncLabConfig lab;
  bool bound_ok = false;
  std::string error;  ///< why there is no bound or no measurement (bound_ok tells which)
  timing::SyncParams params;
  timing::LatencyBound bound = {};
  std::vector<SimNs> samples_ns;
  SampleStats stats;
  uint32_t wanted = 0;   ///< measurements asked for
  uint32_t outside = 0;  ///< samples outside [best, worst]
  uint32_t lost = 0;     ///< presses whose LED never came (sync-latency)
  uint64_t syncs = 0;    ///< SYNC frames on the bus during the run
  SimNs duration_ns = 0;
  uint64_t events = 0;
  /// A bound exists, every wanted measurement was made and lies inside it.
  bool ok = false;
};

/// §5.2: `answers` round trips. c.stations as given (≥ 2). Not measured
/// (error set, not ok) when the SYNC period is not above the bound's worst
/// round trip: an answer could then come after the next SYNC.
SyncResult sync_roundtrip_scenario(const LineConfig& c, const SyncLabConfig& lab, uint32_t answers,
                                   EventLog* log, const Progress& progress);
/// §5.3: `presses` presses of B's START, the LED is A's lab LED.
SyncResult sync_latency_scenario(const LineConfig& c, const SyncLabConfig& lab, uint32_t presses,
                                 EventLog* log, const Progress& progress);

/// The bound's inputs for `line` as commissioned by the SYNC labs (every
/// Arduino up): frames, the line's analysis, the node timing model.
Status sync_params_for(Line& line, const SyncLabConfig& lab, timing::SyncParams* p);

/// §11 at one bit rate: the three paths side by side.
struct AlternativeResult {
  uint32_t bitrate_kbit = 0;
  LatencyResult modbus;   ///< PC-controlled, button and LED on the PC's Arduino
  LatencyResult canopen;  ///< PC-controlled, button and LED on another Arduino
  LatencyResult arduino;  ///< control process on Arduino A, button and LED on B
  bool ok = false;
};
AlternativeResult alternative_scenario(const LineConfig& c, uint32_t bitrate_kbit, uint32_t presses,
                                       EventLog* log, const Progress& progress);

}  // namespace sim
}  // namespace mb2co
