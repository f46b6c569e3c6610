// The scenarios mb2co-lab runs on a simulated line, each a function of its
// configuration and seed only. Results are plain data; the lab formats them.
//   run     bottles flow on every station, RUN LEDs on
//   stop2   STOP2 at each station k in turn: k and k+1 stop, LEDs of
//           k-1..k+2 show it, START brings them back
//   latency seed 000 §11: button → LED over Modbus only and over Modbus +
//           CANopen, many presses at random phases, against the bound
//   faults  frame corruption, bus-off, a neighbour power-cycled, a serial
//           cable unplugged: STOP2 never lost, lost neighbours unknown within
//           the heartbeat consumer time, plants kept safe
#pragma once
#include <stdint.h>

#include <functional>
#include <string>
#include <vector>

#include "sim/lab_bound.h"
#include "sim/line.h"

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

struct StationSummary {
  bool running = false;  ///< gateway RUN state at the end
  uint8_t leds = 0;
  uint32_t bottles_filled = 0;
  uint32_t handed_off = 0;
  uint32_t overfilled = 0;
  uint64_t spilled_ul = 0;
  uint64_t pc_cycles = 0;
  uint64_t pc_overruns = 0;
  uint64_t pc_failures = 0;
  uint64_t passes = 0;
  uint32_t local_stop2_seen = 0;  ///< STOP2 events the PC saw on its own panel
  uint32_t prev_stop2_seen = 0;   ///< … from the previous station
  uint64_t unsafe_while_lost = 0;
  uint64_t link_losses = 0;
};

struct LineSummary {
  std::vector<StationSummary> stations;
  std::vector<TimelineEvent> timeline;
  uint64_t can_frames = 0;
  uint64_t error_frames = 0;
  uint64_t ack_error_frames = 0;  ///< of error_frames: no other station powered to acknowledge
  uint64_t rx_overflows = 0;
  double bus_load = 0;  ///< busy time / run time
  SimNs duration_ns = 0;
  uint64_t events = 0;
};

// ---- run -------------------------------------------------------------------
struct RunResult {
  LineSummary line;
  bool all_running = false;
  bool leds_ok = false;  ///< every station shows itself and its neighbours running
  bool ok = false;
};
RunResult run_scenario(const LineConfig& c, SimNs duration_ns, EventLog* log, const Progress& progress);
/// The shortest run (whole simulated seconds) in which the run scenario's
/// criterion "every station fills a bottle" can be met: START (pressed up to
/// 1.2 s after power-on), the first bottle's way to the valve and its filling
/// with this configuration's plant, and 1 s of slack. Shorter runs are refused.
uint32_t run_min_duration_s(const LineConfig& c);

// ---- stop2 -----------------------------------------------------------------
struct Stop2Case {
  int k = 0;                  ///< station pressed (0-based)
  std::vector<int> stopped;   ///< stations whose RUN went 0
  std::vector<int> expected;  ///< k and k+1 (if any)
  bool leds_ok = false;       ///< LEDs of k-1..k+2 as expected
  std::vector<std::string> led_errors;
  SimNs own_led_ns = 0;    ///< press → own RUN LED off
  SimNs next_led_ns = 0;   ///< press → next station's RUN LED off (0: none)
  bool restarted = false;  ///< START brought every station back
  bool ok = false;
};
struct Stop2Result {
  LineSummary line;
  std::vector<Stop2Case> cases;
  bool ok = false;
};
Stop2Result stop2_scenario(const LineConfig& c, EventLog* log, const Progress& progress);

// ---- latency ---------------------------------------------------------------
struct LatencyCase {
  uint32_t bitrate_kbit = 500;
  bool remote = false;  ///< Modbus + CANopen (else Modbus only)
  /// Presses at the phasings the bound assumes, found by a deterministic
  /// search (--worst), instead of `presses` presses at random phases.
  bool worst = false;
};
struct LatencyResult {
  LatencyCase c;
  LabBound bound;
  std::vector<SimNs> samples_ns;  ///< press → LED on, per press
  uint32_t lost = 0;              ///< presses whose LED never came (within 1 s)
  uint64_t lab_frames_lost = 0;   ///< button/LED PDOs dropped in receive overflows
  uint32_t outside = 0;           ///< samples outside [best, worst]
  SimNs min_ns = 0, max_ns = 0, p99_ns = 0;
  double mean_ns = 0;
  uint64_t rx_overflows = 0;
  uint64_t t15_discards = 0;
  SimNs duration_ns = 0;
  uint64_t events = 0;
  /// The bound exists and every measurement lies inside it. Lost presses are
  /// not measurements (the bound assumes no frame is lost): reported apart.
  bool ok = false;
};
/// `c.lab_pc`/`c.lab_remote` default to stations 1 and 2 when unset.
LatencyResult latency_scenario(LineConfig c, const LatencyCase& lc, uint32_t presses, EventLog* log,
                               const Progress& progress);

// ---- faults ----------------------------------------------------------------
struct FaultCheck {
  std::string what;
  bool ok = false;
  std::string detail;
};
struct FaultsResult {
  LineSummary line;
  std::vector<FaultCheck> checks;
  std::vector<std::string> notes;  ///< findings outside the invariants
  bool ok = false;
};
/// Needs at least 4 stations.
FaultsResult faults_scenario(const LineConfig& c, EventLog* log, const Progress& progress);

/// Summary of a line at the end of a run.
LineSummary summarize(Line& line);

}  // namespace sim
}  // namespace mb2co
