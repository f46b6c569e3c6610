// The INI layer of CiA 306 files: text -> sections of key/value lines with
// their line numbers. Internal to the reader (eds_reader.cpp).
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "eds_model.h"

namespace mb2co {
namespace eds {
namespace detail {

struct Entry {
  std::string key;    ///< as spelled, trimmed
  std::string value;  ///< trimmed
  int line;
};

struct Section {
  std::string name;            ///< between the brackets, trimmed
  int line;                    ///< of the [header]
  std::vector<Entry> entries;  ///< file order; keys unique case-insensitively
  /// Case-insensitive lookup (nullptr: absent).
  const Entry* find(const std::string& key) const;
  KeyValues key_values() const;
};

/// The first error; line < 0: none yet.
struct LineError {
  int line = -1;
  std::string what;
};

/// Splits `text` into sections. False with *error set on the first malformed
/// line: a control character (other than tab; NUL included), a header
/// without ']', a section or key that appears twice (names and keys compare
/// case-insensitively), a line without '=', an empty key, a key before the
/// first section. *last_line: the number of lines read (at least 1).
bool split_sections(std::string_view text, std::vector<Section>* sections, LineError* error, int* last_line);

}  // namespace detail
}  // namespace eds
}  // namespace mb2co
