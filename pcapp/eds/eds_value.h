// Values in CiA 306 text: numbers, $NODEID expressions, strings and hex dumps,
// turned into the bytes the bus carries (little-endian) and back.
//
// Numbers (CiA 306): decimal ("42", "-5"), hexadecimal ("0x2A"), octal with
// a leading 0 ("052"). Integer values may be `$NODEID`, `$NODEID+N` or
// `N+$NODEID` (node-id relative). REAL32/REAL64: a finite decimal number
// ("1.5", "-2e3"). VISIBLE_STRING: the text itself (printable ASCII).
// OCTET_STRING, UNICODE_STRING (UTF-16LE bytes) and DOMAIN: a hex dump, two
// digits per byte ("0102AB").
#pragma once
#include <stdint.h>

#include <optional>
#include <string>
#include <string_view>

#include "eds_model.h"

namespace mb2co {
namespace eds {

/// A value or why the text is not one of its type (one line, no position).
struct ValueResult {
  std::optional<Value> value;
  std::string error;
};

/// Parses `text` as a value of `type`. With a node id (1..127) a $NODEID
/// expression is evaluated (the result is not node-id relative); without,
/// it is kept symbolic (Value::node_id_relative, bytes = the base).
/// Range: the value (and base + node id when evaluated) must fit the type.
ValueResult parse_value(DataType type, std::string_view text, std::optional<uint8_t> node_id = std::nullopt);

/// The text parse_value() reads back as the same value (unsigned integers in
/// hex, signed in decimal, reals shortest round-trip, strings as they are,
/// byte types as a hex dump; node-id relative values as `$NODEID+0x...`).
/// A VISIBLE_STRING with leading/trailing blanks or non-printable bytes has
/// no such text; it is written as it is.
std::string format_value(DataType type, const Value& value);

/// The value on node `node_id`: a node-id relative value plus the node id
/// (nullopt when that no longer fits the type), any other value as it is.
std::optional<Value> resolve(DataType type, const Value& value, uint8_t node_id);

/// Order of two values of a numeric type: <0, 0, >0. nullopt when the type
/// is not numeric or either value is node-id relative (no order without a node).
std::optional<int> compare_values(DataType type, const Value& a, const Value& b);

/// A value for sub-object `sub` from user text (e.g. a typed SDO write via a
/// node's EDS): parse_value() with the sub's data type, then its
/// LowLimit/HighLimit (limits resolved with the node id when given).
ValueResult parse_value_for(const SubObject& sub, std::string_view text,
                            std::optional<uint8_t> node_id = std::nullopt);

/// What configuring node `node_id` from a DCF writes into `sub`: its
/// ParameterValue, else its DefaultValue, resolved with the node id; nullopt
/// when it has neither or the value does not fit the type.
std::optional<Value> configured_value(const SubObject& sub, uint8_t node_id);

/// An unsigned integer in CiA 306 notation (decimal, 0x hex, 0 octal), with
/// no sign and no $NODEID; nullopt when it is not one or exceeds `max`.
std::optional<uint64_t> parse_unsigned(std::string_view text, uint64_t max);

}  // namespace eds
}  // namespace mb2co
