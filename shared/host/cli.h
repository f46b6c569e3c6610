// The command-line convention of every non-Qt program (docs/cli.md): an
// option table per (sub)command, from which the parser, --help, --version and
// the bash completion (--list-options) all come, so they cannot disagree.
// Host-only (std::string, std::vector).
//
//   PROGRAM [GLOBAL OPTION]... [COMMAND] [--name VALUE | --name=VALUE | -x VALUE | --flag]... [OPERAND]...
//
// Values are checked against their kind while parsing (a bad bit rate is a
// usage error before anything runs). Exit status: 0 done, 1 runtime error,
// 2 usage error; each error is one line "PROGRAM: ..." on stderr.
#pragma once
#include <stdint.h>

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "host/cli_values.h"
#include "host/status.h"

namespace mb2co {
namespace cli {

constexpr int kExitDone = 0;
constexpr int kExitRuntime = 1;
constexpr int kExitUsage = 2;

/// The project's one version string (CMake project(VERSION)).
const char* version();

enum class Kind : uint8_t {
  kFlag,      ///< no value
  kText,      ///< any non-empty value
  kFile,      ///< a path (completion offers files)
  kDir,       ///< a directory (completion offers directories)
  kChoice,    ///< one of `choices`
  kUint,      ///< decimal within [min, max]
  kBitrate,   ///< parse_bitrate within [min, max] (or one of `bitrates` when set)
  kBitrates,  ///< parse_bitrate_list, each one of `bitrates`
  kParity,    ///< parse_parity
  kDuration,  ///< parse_duration_ms within [min, max] ms
  kRefused,   ///< known but not ours: refused as "NAME `help`", hidden
};

struct Option {
  std::string name;     ///< "--bitrate"
  char short_name = 0;  ///< 'i' for -i, 0 for none
  Kind kind = Kind::kFlag;
  std::string value_name;            ///< "B" in "--bitrate B" (empty for a flag)
  std::string help;                  ///< one line or several ('\n'), defaults included
  std::vector<std::string> choices;  ///< kChoice
  uint64_t min = 0;                  ///< kUint, kBitrate, kDuration
  uint64_t max = UINT64_MAX;
  std::vector<uint32_t> bitrates;  ///< kBitrate (optional), kBitrates: allowed bit/s

  /// Also reachable as "-c".
  Option with_short(char c) const;
  bool takes_value() const { return kind != Kind::kFlag && kind != Kind::kRefused; }
};

// Table builders, so a table reads as one line per option.
Option flag(std::string name, std::string help);
Option text(std::string name, std::string value_name, std::string help);
Option file(std::string name, std::string value_name, std::string help);
Option dir(std::string name, std::string value_name, std::string help);
Option choice(std::string name, std::vector<std::string> choices, std::string help);
Option uint_range(std::string name, std::string value_name, uint64_t min, uint64_t max, std::string help);
Option bitrate(std::string name, uint32_t min_bps, uint32_t max_bps, std::string help);
Option bitrate_of(std::string name, std::vector<uint32_t> allowed_bps, std::string help);
Option bitrate_list(std::string name, std::vector<uint32_t> allowed_bps, std::string help);
Option parity(std::string name, std::string help);
Option duration(std::string name, uint64_t min_ms, uint64_t max_ms, std::string help);
/// An option of another program, refused as "NAME `why`" (not in --help).
Option refused(std::string name, std::string why);

struct Command {
  std::string name;      ///< "rta"; "" for a program without subcommands
  std::string summary;   ///< one line for the program's --help
  std::string operands;  ///< "[FILE.csv]" for the usage line ("" for none)
  size_t max_operands = 0;
  std::vector<Option> options;  ///< --help, --version are implied
  /// Fewer operands are a usage error "missing operand: NAME OPERANDS".
  size_t min_operands = 0;
};

struct Program {
  std::string name;               ///< "mb2co-timing"
  std::string description;        ///< a few lines for --help
  std::vector<Command> commands;  ///< one Command named "" when there are no subcommands
  /// Options of every command, also accepted before the command's name
  /// ("mb2co-master -i can0 read ..."); in every command's --help.
  std::vector<Option> global_options;
  std::string footer;  ///< exit statuses, notes (end of every --help)
};

/// The options and operands of one invocation, checked against the table.
class Args {
 public:
  const Command* command = nullptr;
  std::vector<std::string> operands;

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  /// The value as given ("" for a flag); `fallback` when absent.
  std::string get(const std::string& name, const std::string& fallback = "") const;
  /// Typed look-ups of values the parser already checked; `fallback` when absent.
  uint64_t uint(const std::string& name, uint64_t fallback) const;
  uint32_t bitrate_bps(const std::string& name, uint32_t fallback) const;
  std::vector<uint32_t> bitrates_bps(const std::string& name, std::vector<uint32_t> fallback) const;
  Parity parity(const std::string& name, Parity fallback) const;
  uint64_t duration_ms(const std::string& name, uint64_t fallback) const;

  void set(const std::string& name, std::string value) { values_[name] = std::move(value); }

 private:
  std::map<std::string, std::string> values_;  ///< "--name" → value
};

enum class Action : uint8_t {
  kRun,          ///< `args` is ready
  kHelp,         ///< print `text` on stdout, exit 0
  kVersion,      ///< same
  kListOptions,  ///< same (the words bash completion offers)
  kUsageError,   ///< print "PROGRAM: `text`" on stderr, exit 2
};

struct Parsed {
  Action action = Action::kRun;
  std::string text;
  Args args;
};

/// Parses argv[1..] against `program`'s tables. --help/-h anywhere gives the
/// help of the command named (or of the program); --version the version;
/// a hidden --list-options the words for bash completion.
Parsed parse(const Program& program, int argc, const char* const* argv);

/// Prints what parse() found for every action but kRun and returns the exit
/// status; returns -1 for kRun (the program goes on with `parsed.args`).
int finish_early(const Program& program, const Parsed& parsed, std::ostream& out, std::ostream& err);

/// The --help text of `command` (nullptr: of the program).
std::string help_text(const Program& program, const Command* command);

/// One line per word completion offers: commands, then "--name KIND [CHOICES]".
std::string list_options(const Program& program, const Command* command);

/// Checks one value against its option's kind (the parser's check).
Status check_value(const Option& option, const std::string& value);

}  // namespace cli
}  // namespace mb2co
