// Reads a CAN message set from CSV:
//   name,id,ext,dlc,period_us[,deadline_us][,jitter_us][,c_us][,bits]
// Columns in any order, named by the first non-comment line. '#' starts a
// comment line; blank lines are skipped. id is decimal or 0x-hex; ext 0/1;
// deadline_us defaults to period_us, jitter_us to 0; c_us (transmission
// time) or bits (frame length) overrides what the DLC gives, for textbook
// sets that state C directly. Times are decimal µs: c_us with up to three
// decimals (ns), the others whole ("1040.0" is 1040). The file is UTF-8 (a
// byte order mark is skipped): bytes that are not, and NUL, are errors, so
// names reach JSON output intact. Every error names FILE:LINE:COL.
#pragma once
#include <string>
#include <vector>

#include "host/status.h"
#include "timing/message_set.h"

namespace mb2co {
namespace timing_cli {

/// Parses `text` (the contents of `source`, used in messages). On success
/// fills `out` in file order; otherwise fails with one line
/// "source:line:col: what".
Status parse_message_csv(const std::string& text, const std::string& source,
                         std::vector<timing::MessageSpec>& out);

/// Reads the file at `path` and parses it.
Status read_message_csv(const std::string& path, std::vector<timing::MessageSpec>& out);

}  // namespace timing_cli
}  // namespace mb2co
