// The CiA 301 SDO abort codes in words, for one-line errors (table 22).
#pragma once
#include <stdint.h>

namespace mb2co {
namespace master {

/// The CiA 301 description of `code`, or "unknown abort code".
const char* abort_text(uint32_t code);

}  // namespace master
}  // namespace mb2co
