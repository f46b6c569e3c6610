// What the two periodic producer commands (sync, time) share: their
// --period/--count/--cob-id options and the bus loop that runs until the
// last frame is sent.
#pragma once
#include <cstdint>
#include <functional>
#include <ostream>

#include "bus_loop.h"
#include "cli_options.h"

namespace mb2co {
namespace master {

/// --period MS (0: none), --count N (default 1), --cob-id ID (11 bits).
struct PeriodicOptions {
  uint64_t period_ms = 0;
  uint64_t count = 1;
  uint64_t cob_id = 0;
};

/// Reads the options of command `what` (ranges checked by the parser's
/// table), `default_cob_id` when --cob-id is absent: kExitOk, or kExitUsage
/// with the reason printed ("WHAT: --count above 1 needs --period MS").
int read_periodic_options(const char* what, const Options& o, uint16_t default_cob_id, PeriodicOptions* p,
                          std::ostream& err);

/// Runs `bus` until `done` or an interrupt: kExitOk, or kExitInterrupted.
int run_until_done(BusLoop& bus, const std::function<bool()>& done);

}  // namespace master
}  // namespace mb2co
