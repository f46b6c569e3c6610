// The wording of a usage error (docs/cli.md), one place for the option-table
// layer (cli.h) and for mb2co-plant's QCommandLineParser: every program says
// an unknown option, a near miss and a missing operand the same way. Each
// function returns the text after "PROGRAM: " (one line, no newline).
// Host-only.
#pragma once
#include <stddef.h>

#include <string>
#include <vector>

namespace mb2co {
namespace cli {

/// Edits (insert, delete, change one character, swap two neighbours) that
/// turn `a` into `b`: the optimal string alignment distance git's "did you
/// mean" uses.
size_t edit_distance(const std::string& a, const std::string& b);

/// The one word of `known` closest to `word` when it is near enough to be a
/// typing slip ("--bitrate" for "--bitrates", "--stations" for "--statoins"):
/// at most a third of the word's letters (dashes not counted) and at most 3
/// edits, or `word` a prefix of it. "" when none is, or when two are equally near.
std::string nearest_word(const std::string& word, const std::vector<std::string>& known);

/// "(try PROGRAM --help)", "(try PROGRAM COMMAND --help)" for a non-empty command.
std::string try_help(const std::string& program, const std::string& command);

/// "unknown option --x (try PROGRAM CMD --help)", or with a near option
/// "unknown option --bitrate, did you mean --bitrates? (try mb2co-lab --help)".
std::string unknown_option(const std::string& program, const std::string& command, const std::string& word,
                           const std::vector<std::string>& known);

/// "missing operand: CMD OPERANDS (try PROGRAM CMD --help)"; without a
/// command "missing operand: OPERANDS (try PROGRAM --help)".
std::string missing_operand(const std::string& program, const std::string& command,
                            const std::string& operands);

/// "--x must be WHAT, got "VALUE"": a bad value.
std::string bad_value(const std::string& option, const std::string& what, const std::string& value);

}  // namespace cli
}  // namespace mb2co
