// Command line of mb2co-lab (the convention of docs/cli.md, shared/host/cli.h).
// Every bad option is one line of text and exit 2.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/cli.h"
#include "sim/line.h"

namespace mb2co {
namespace lab {

enum class Scenario {
  kDefault,
  kRun,
  kStop2,
  kLatency,
  kFaults,
  kSyncRoundtrip,
  kSyncLatency,
  kSyncProcessing,
  kAlternative
};

struct Options {
  Scenario scenario = Scenario::kDefault;
  sim::LineConfig line;                                    ///< stations, seed, timing
  std::vector<uint32_t> bitrates = {125, 250, 500, 1000};  ///< kbit/s, latency cases in this order
  uint32_t presses = 1000;
  bool worst = false;  ///< latency: search the worst phasings instead of random presses
  std::string out_dir = "out";
  std::string trace_path;        ///< --trace: the bus as a candump -L log ("" none)
  uint32_t duration_s = 30;      ///< run scenario
  std::string firmware = "uno";  ///< uno | fast
  bool quiet = false;
  bool events = false;  ///< --events: write events.csv (every event of the runs, ~30 MB by default)
  // The SYNC labs (seed 000 §5) and sync-processing.
  uint32_t syncs = 1000;              ///< round trips per bit rate (sync-roundtrip), SYNCs (sync-processing)
  uint32_t sync_period_us = 10000;    ///< 1006h of the SYNC producer
  uint32_t transmission_type = 1;     ///< of the synchronous TPDO, 1..240
  uint32_t bound_sync_period_us = 0;  ///< 0: the configured period; else the bound assumes this one
  std::string elf;                    ///< sync-processing: the image ("" = the built gateway image)
};

/// The option table of mb2co-lab (help, parser and completion come from it).
const cli::Program& program();
/// Fills `out` from a parse of program(); fails (a usage error) for
/// combinations the table cannot express.
Status apply_options(const cli::Args& args, Options* out);
const char* scenario_name(Scenario s);

}  // namespace lab
}  // namespace mb2co
