// Typed values on mb2co-master's command line: the TYPE words (u8 ... d)
// as CiA 301 data types, values parsed and printed in CiA 306 notation
// (pcapp/eds), so what `read` prints `write` reads back.
#pragma once
#include <optional>
#include <string>

#include "eds_model.h"
#include "host/status.h"

namespace mb2co {
namespace master {

/// "u32" → UNSIGNED32, ... ; nullopt for an unknown word.
std::optional<eds::DataType> type_of_word(const std::string& word);
/// The words, for messages: "b u8 u16 u24 u32 u64 i8 i16 i32 i64 r32 r64 vs os us d".
const char* type_words();

/// Where a read/write gets its type: the TYPE word if given, else the EDS
/// (--eds) entry of (index, sub); fails when neither says.
Status resolve_type(const std::string& word, const std::string& eds_path, uint16_t index, uint8_t sub,
                    eds::DataType* type);

}  // namespace master
}  // namespace mb2co
