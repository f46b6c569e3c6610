// The subcommands of mb2co-timing, each given parsed options. A failure's
// message is one line without the program's prefix; it is a usage error
// (exit 2) unless the command sets *runtime_failure (a file it could not
// read or write: exit 1).
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "options.h"
#include "timing/message_set.h"

namespace mb2co {
namespace timing_cli {

Status frame_command(const Options& o, std::ostream& out);
Status load_command(const Options& o, std::ostream& out, bool* runtime_failure);
/// `*deadline_missed` is set when --check is given and a message misses its
/// deadline (exit status 3: an answer, not a failure).
Status rta_command(const Options& o, std::ostream& out, bool* deadline_missed, bool* runtime_failure);
Status latency_command(const Options& o, std::ostream& out);

/// The message set of load/rta: FILE.csv (needs --bitrate) or --line N.
/// Sorted into priority order; *bitrate_bps set.
Status message_set_option(const Options& o, std::vector<timing::MessageSpec>& set, uint32_t* bitrate_bps,
                          bool* runtime_failure);

}  // namespace timing_cli
}  // namespace mb2co
