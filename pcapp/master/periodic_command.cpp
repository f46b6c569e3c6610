#include "periodic_command.h"

#include <string>

#include "commands.h"
#include "exit_codes.h"
#include "number_words.h"

namespace mb2co {
namespace master {

int read_periodic_options(const char* what, const Options& o, uint16_t default_cob_id, PeriodicOptions* p,
                          std::ostream& err) {
  p->period_ms = o.args.uint("--period", 0);
  p->count = o.args.uint("--count", 1);
  p->cob_id = default_cob_id;
  if (o.args.has("--cob-id")) {
    const Status s = parse_number(o.args.get("--cob-id"), 0x7FF, "--cob-id", &p->cob_id);
    if (!s) return fail(err, kExitUsage, std::string(what) + ": " + s.message());
  }
  if (p->count > 1 && p->period_ms == 0)
    return fail(err, kExitUsage, std::string(what) + ": --count above 1 needs --period MS");
  return kExitOk;
}

int run_until_done(BusLoop& bus, const std::function<bool()>& done) {
  while (!done() && !bus.interrupted()) bus.run_until(done, BusLoop::kLongestRunUs);
  return bus.interrupted() ? kExitInterrupted : kExitOk;
}

}  // namespace master
}  // namespace mb2co
