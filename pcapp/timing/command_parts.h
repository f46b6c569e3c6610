// The subcommands of mb2co-timing, each given parsed options. On an error
// they set `error` (one line, no prefix) and return 1.
#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "options.h"
#include "timing/message_set.h"

namespace mb2co {
namespace timing_cli {

int frame_command(const Options& o, std::ostream& out, std::string& error);
int load_command(const Options& o, std::ostream& out, std::string& error);
int rta_command(const Options& o, std::ostream& out, std::string& error);
int latency_command(const Options& o, std::ostream& out, std::string& error);

/// The message set of load/rta: FILE.csv (needs --bitrate) or --line N.
/// Sorted into priority order; *bitrate_bps set.
bool message_set_option(const Options& o, std::vector<timing::MessageSpec>& set, uint32_t* bitrate_bps,
                        std::string& error);

}  // namespace timing_cli
}  // namespace mb2co
