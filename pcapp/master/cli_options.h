// mb2co-master's command line: global options, then a command and its
// words. Numbers follow can-utils/cocomm habits: 0x.. or ..h hex, else
// decimal; node ids 1..127 ("all" where a broadcast makes sense).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"

namespace mb2co {
namespace master {

struct Options {
  std::string iface = "can0";  ///< -i IFACE
  uint32_t timeout_ms = 1000;  ///< -t MS: SDO client timeout (CiA 301 leaves it to us)
  bool json = false;           ///< --json: one JSON object per line
  uint16_t heartbeat_ms = 0;   ///< --heartbeat MS: watchdog consumer time for SDO (0: none)
  std::string eds;             ///< --eds FILE: types for read/write
  /// --via-modbus PORT[:SLAVE]: the gateway's serial device ("": SocketCAN)
  /// and its Modbus address; --baud: the line's rate (8N1).
  std::string gateway_port;
  uint8_t gateway_slave = 1;
  uint32_t baud = 115200;
  std::string command;
  std::vector<std::string> words;  ///< the command's arguments and options, in order
};

/// Parses argv. Fails with one line (no newline) for an unknown option, a
/// missing command or a bad number.
Status parse_options(int argc, char** argv, Options* out);
/// Why a command (or option) cannot run through a gateway: one line,
/// "watch needs raw CAN frames (...)"; "" when it can.
std::string via_modbus_refusal(const Options& o);
/// The same reason for a command that needs the SocketCAN loop.
std::string needs_can_frames(const std::string& what);

/// The usage text (printed for --help and after a usage error).
const char* usage_text();

/// "0x1018", "1018h", "4120" → value; fails when not a number or above `max`.
Status parse_number(const std::string& text, uint64_t max, const char* what, uint64_t* value);
/// 1..127, or 0 for "all"/"0" when `allow_all`.
Status parse_node_id(const std::string& text, bool allow_all, uint8_t* node_id);

/// "1,2,5-7" → node ids in that order; fails with the offending word.
Status parse_node_list(const std::string& text, std::vector<uint8_t>* nodes);
/// INDEX (0..FFFFh) and SUB (0..255) as parse_number reads them.
Status parse_index_sub(const std::string& index, const std::string& sub, uint16_t* i, uint8_t* s);

/// Pulls "--name VALUE" (or "--name" alone when `flag`) out of `words`;
/// true when it was there. `value` may be null for a flag.
bool take_option(std::vector<std::string>* words, const std::string& name, bool flag, std::string* value);

}  // namespace master
}  // namespace mb2co
