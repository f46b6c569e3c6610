// One request line of CiA 309-3's ASCII mapping, parsed as CANopenNode's
// gateway reads it (309/CO_gateway_ascii.c):
//
//   [SEQ] [[NET] NODE] r[ead] INDEX SUB [TYPE]
//   [SEQ] [[NET] NODE] w[rite] INDEX SUB TYPE VALUE
//   [SEQ] [[NET] NODE] start | stop | preop[erational] | reset node | reset comm[unication]
//   [SEQ] [NET] set network N | set node N | set sdo_timeout MS | set sdo_block 0|1
//   [SEQ] set events 0|1 | info | log | help [datatype]
//
// Tokens are separated by anything that is not a printable ASCII character
// (space, tab, CR, NUL, bytes >= 80h), '#' starts a comment to the end of
// the line, words are case-insensitive. Numbers as strtoul(..., 0) reads
// them: INDEX 0x1017 is 1017h, 1017 is decimal (03F9h). NODE 0 or `all`
// (ours) is every node for NMT. Plain C++ without OS or Qt; a pure function
// of the line and the connection's defaults, so it can be fuzzed.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <string>
#include <vector>

#include "ascii_response.h"
#include "ascii_values.h"

namespace mb2co {
namespace master {
namespace ascii {

/// What the parse needs of the connection and the gateway.
struct ParseContext {
  uint16_t net = 1;           ///< the one net this gateway serves
  int16_t default_node = -1;  ///< `set node` (-1: none yet)
  uint32_t last_seq = 0;      ///< answers a line without a readable [SEQ] (as CANopenNode)
  size_t max_value_bytes = 65536;
};

struct Request {
  enum class Kind : uint8_t {
    kEmpty,  ///< blank or comment only: answered with an empty line
    kError,  ///< answered with `error`
    kRead,
    kWrite,
    kNmt,
    kSetNetwork,
    kSetNode,
    kSetSdoTimeout,
    kSetSdoBlock,
    kSetEvents,
    kInfo,
    kLog,
    kHelp,
    kHelpDatatype,
  };
  Kind kind = Kind::kEmpty;
  uint32_t seq = 0;
  bool seq_given = false;  ///< [SEQ] was read (else seq is the context's last_seq)
  GatewayError error = GatewayError::kNone;
  uint8_t node = 0;  ///< kRead, kWrite, kNmt (0: all, NMT only)
  uint16_t index = 0;
  uint8_t sub = 0;
  DataType type = DataType::kHex;  ///< kRead without TYPE: hex
  std::vector<uint8_t> value;      ///< kWrite: the bytes to write
  uint8_t nmt = 0;                 ///< kNmt: the CiA 301 command byte (01h start, ...)
  uint32_t number = 0;             ///< kSet*: the value
};

/// Parses one line (without its LF; a CR is a blank like any other).
Request parse_request(const std::string& line, const ParseContext& context);

/// The [SEQ] at the start of `text` (the first bytes of an overlong line),
/// or `fallback` when there is none.
uint32_t leading_seq(const std::string& text, uint32_t fallback);

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
