// Command-line options of mb2co-timing: parsing against a table of known
// options per subcommand, typed look-ups with one-line errors, and the
// options that describe the line's CANopen configuration.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "host/cli.h"
#include "host/status.h"
#include "report.h"
#include "timing/can_bits.h"
#include "timing/line_config.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {

enum Command : unsigned { kFrame = 1, kLoad = 2, kRta = 4, kLatency = 8 };

struct Options {
  Command command = kFrame;
  std::vector<std::string> positional;
  cli::Args args;  ///< checked against the command's table (program())

  bool has(const std::string& name) const { return args.has(name); }
  std::string get(const std::string& name) const { return args.get(name); }
};

/// The option tables of mb2co-timing, one per command (help, parser and
/// completion come from them). Defaults shown are those of the code's structs.
const cli::Program& program();

/// The Options of a parse that found a command to run.
Options options_of(const cli::Args& args);

/// An unsigned option within [min, max]; `fallback` when absent.
Status uint_option(const Options& o, const std::string& name, uint64_t min, uint64_t max, uint64_t fallback,
                   uint64_t* value);

Status format_option(const Options& o, Format* format);
Status frame_bits_option(const Options& o, timing::WorstCase* convention);
/// "course" or "davis".
const char* frame_bits_name(timing::WorstCase convention);

/// The line configuration from --line N and the line options (defaults of
/// LineCanConfig otherwise); --bitrate sets its bit rate.
Status line_config_option(const Options& o, timing::LineCanConfig* cfg);

/// Human-readable reason for a LineStatus.
std::string line_status_text(timing::LineStatus status);

/// Node ids of `latency` when --button-node / --pc-node are not given.
constexpr unsigned kDefaultButtonNode = 2;
constexpr unsigned kDefaultPcNode = 1;

}  // namespace timing_cli
}  // namespace mb2co
