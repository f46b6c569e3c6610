// Command-line options of mb2co-timing: parsing against a table of known
// options per subcommand, typed look-ups with one-line errors, and the
// options that describe the line's CANopen configuration.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

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
  std::map<std::string, std::string> values;  ///< "--name" → value ("" for flags)

  bool has(const std::string& name) const { return values.count(name) != 0; }
  const std::string& get(const std::string& name) const { return values.at(name); }
};

/// Parses argv[2..] for `command` (named by argv[1]). Fails on an unknown
/// option, a missing value or a repeated option.
Status parse_options(int argc, char** argv, Options& out);

/// An unsigned option within [min, max]; `fallback` when absent. Accepts a
/// k/M suffix when `scaled` (125k, 1M).
Status uint_option(const Options& o, const std::string& name, uint64_t min, uint64_t max, uint64_t fallback,
                   bool scaled, uint64_t* value);

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

/// The usage text printed by --help, defaults taken from the code's structs.
std::string usage_text();

}  // namespace timing_cli
}  // namespace mb2co
