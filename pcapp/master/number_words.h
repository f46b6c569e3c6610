// The operands of mb2co-master's commands: node ids, indices, sub-indices.
// Numbers follow can-utils/cocomm habits: 0x.. or ..h hex, else decimal;
// node ids 1..127 ("all" where a broadcast makes sense). Each failure is one
// line naming the word, without the program's prefix.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"

namespace mb2co {
namespace master {

/// "0x1018", "1018h", "4120" → value; fails when not a number or above `max`.
Status parse_number(const std::string& text, uint64_t max, const char* what, uint64_t* value);
/// 1..127, or 0 for "all"/"0" when `allow_all`.
Status parse_node_id(const std::string& text, bool allow_all, uint8_t* node_id);
/// "1,2,5-7" → node ids in that order; fails with the offending word.
Status parse_node_list(const std::string& text, std::vector<uint8_t>* nodes);
/// INDEX (hexadecimal even without a mark: 0000..FFFF) and SUB (0..255) as
/// parse_number reads them.
Status parse_index_sub(const std::string& index, const std::string& sub, uint16_t* i, uint8_t* s);

}  // namespace master
}  // namespace mb2co
