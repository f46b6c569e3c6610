// mb2co-lab's scenarios, run one after another into one report: each adds
// its section to the report, its files (CSV, SVG) to what --out receives,
// its simulated time and its verdict.
#pragma once
#include <stdint.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "options.h"
#include "progress_bar.h"
#include "sim/can_trace.h"
#include "sim/event_log.h"

namespace mb2co {
namespace lab {

/// What the runs of one mb2co-lab call have produced so far. Not copyable
/// (the event log points at the trace).
struct LabRun {
  explicit LabRun(const Options& o)
      : bar(!o.quiet && isatty(STDOUT_FILENO) ? stdout : nullptr),
        // Without --events nothing is logged: no line is formatted that would not be written.
        log(o.events) {
    if (!o.trace_path.empty()) log.set_can_trace(&trace);
  }
  LabRun(const LabRun&) = delete;
  LabRun& operator=(const LabRun&) = delete;

  ProgressBar bar;
  sim::CanTrace trace;
  sim::EventLog log;
  std::string report;
  std::vector<std::pair<std::string, std::string>> files;  ///< name in --out, contents
  bool pass = true;                                        ///< every verdict so far passed
  double simulated_s = 0;                                  ///< line time simulated, s
};

/// Runs what `o.scenario` chooses (the default: stop2 then latency) in the
/// report's order; sync-processing runs the AVR image `elf`.
void run_scenarios(const Options& o, const std::string& elf, LabRun* run);

}  // namespace lab
}  // namespace mb2co
