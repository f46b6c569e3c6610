// Reads a plant config file's text: `key = value` lines, `#` comments.
// Portable: the caller reads the file and hands over its bytes.
#pragma once
#include <stddef.h>

#include "plant/plant_config.h"

namespace mb2co {
namespace plant {

/// Parses `length` bytes of `text` (need not be NUL-terminated) on top of the
/// defaults of PlantConfig. Grammar, per line (LF or CRLF):
///   blank | # comment | key = unsigned-decimal [# comment]
/// Every key at most once; every range and cross-check of check_plant_config().
/// On success writes `out` and returns true. On failure returns false, leaves
/// `out` untouched, and fills `error` with a 1-based line and column and a
/// one-line message (line 0 when only the defaults are to blame).
bool parse_plant_config(const char* text, size_t length, PlantConfig& out, ConfigError& error);

}  // namespace plant
}  // namespace mb2co
