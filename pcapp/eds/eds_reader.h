// Reads a CiA 306 EDS or DCF file into an eds::DeviceDescription.
//
// Strict where the standard is clear, so that a master never configures a
// node from a file it misread: every malformed line or inconsistency is one
// error `file:line: what` (the first found), never an exception, a crash or
// a partial model. Accepted: INI syntax with ';' comment lines, CR/LF or LF,
// case-insensitive section names and keys; a key/value line's key and value
// are trimmed of blanks. Required: [FileInfo], [DeviceInfo],
// [MandatoryObjects], and a section for every listed object; every object at
// 1000h or above is listed in one of the three object lists (data-type
// entries below 1000h need not be). CompactSubObj arrays are expanded:
// sub 0 "NrOfObjects" (UNSIGNED8, ro, default = the count), subs 1..N as the
// object's section describes them, named by [xxxxName] (else
// "<ParameterName><sub>"), with ParameterValue from [xxxxValue] and
// Denotation from [xxxxDenotation].
#pragma once
#include <stdint.h>

#include <optional>
#include <string>
#include <string_view>

#include "eds_model.h"

namespace mb2co {
namespace eds {

struct ParseError {
  std::string file;
  int line = 0;  ///< 1-based line the problem is on (a missing section: the last line; 0: no line)
  std::string what;
  /// "file:line: what" (one line); "file: what" when no line is meant.
  std::string text() const {
    return file + (line ? ":" + std::to_string(line) : std::string()) + ": " + what;
  }
};

/// Either a model or the first error.
struct ParseResult {
  std::optional<DeviceDescription> model;
  ParseError error;  ///< meaningful when !model
  explicit operator bool() const { return model.has_value(); }
};

/// Parses the text of an EDS/DCF; `filename` only names it in errors.
/// node_id (1..127): $NODEID expressions are evaluated with it; without it
/// they stay symbolic (Value::node_id_relative).
ParseResult parse(std::string_view text, const std::string& filename,
                  std::optional<uint8_t> node_id = std::nullopt);

/// parse() of a file's contents (an unreadable file is an error at line 0).
ParseResult parse_file(const std::string& path, std::optional<uint8_t> node_id = std::nullopt);

}  // namespace eds
}  // namespace mb2co
