#include "ascii_response.h"

#include <stdio.h>

#include "abort_text.h"

namespace mb2co {
namespace master {
namespace ascii {

const char* gateway_error_text(GatewayError e) {
  struct Row {
    GatewayError code;
    const char* text;
  };
  static const Row kRows[] = {
      {GatewayError::kRequestNotSupported, "Request not supported."},
      {GatewayError::kSyntax, "Syntax error."},
      {GatewayError::kInternalState, "Request not processed due to internal state."},
      {GatewayError::kTimeOut, "Time-out."},
      {GatewayError::kNoDefaultNet, "No default net set."},
      {GatewayError::kNoDefaultNode, "No default node set."},
      {GatewayError::kUnsupportedNet, "Unsupported net."},
      {GatewayError::kUnsupportedNode, "Unsupported node."},
      {GatewayError::kLostGuarding, "Lost guarding message."},
      {GatewayError::kLostConnection, "Lost connection."},
      {GatewayError::kHeartbeatStarted, "Heartbeat started."},
      {GatewayError::kHeartbeatLost, "Heartbeat lost."},
      {GatewayError::kWrongNmtState, "Wrong NMT state."},
      {GatewayError::kBootUp, "Boot-up."},
      {GatewayError::kErrorPassive, "Error passive."},
      {GatewayError::kBusOff, "Bus off."},
      {GatewayError::kCanOverflow, "CAN buffer overflow."},
      {GatewayError::kCanInit, "CAN init."},
      {GatewayError::kCanActive, "CAN active (at init or start-up)."},
      {GatewayError::kPdoAlreadyUsed, "PDO already used."},
      {GatewayError::kPdoLengthExceeded, "PDO length exceeded."},
      {GatewayError::kOutOfMemory, "Running out of memory."},
  };
  for (const Row& r : kRows)
    if (r.code == e) return r.text;
  return "-";
}

std::string ok_line(uint32_t seq) {
  return "[" + std::to_string(seq) + "] OK\r\n";
}

std::string value_line(uint32_t seq, const std::string& text) {
  return "[" + std::to_string(seq) + "] " + text + "\r\n";
}

std::string error_line(uint32_t seq, GatewayError e) {
  return "[" + std::to_string(seq) + "] ERROR:" + std::to_string(static_cast<unsigned>(e)) + " #" +
         gateway_error_text(e) + "\r\n";
}

std::string abort_line(uint32_t seq, uint32_t abort_code) {
  char code[16];
  snprintf(code, sizeof code, "0x%08X", abort_code);
  return "[" + std::to_string(seq) + "] ERROR:" + code + " #" + abort_text(abort_code) + "\r\n";
}

const char* help_text() {
  return "\n"
         "Each request is one line: [SEQ] then, as the command needs, [[NET] NODE] and:\n"
         "  r[ead] INDEX SUB [TYPE]          SDO upload (no TYPE: the bytes in hex)\n"
         "  w[rite] INDEX SUB TYPE VALUE     SDO download\n"
         "  start | stop | preop[erational]  NMT command (NODE 0 or all: every node)\n"
         "  reset node | reset comm[unication]\n"
         "  set network NET                  the default net (this gateway is net 1)\n"
         "  set node NODE                    the default node\n"
         "  set sdo_timeout MS               SDO client timeout of this connection\n"
         "  set sdo_block 0|1                SDO block transfer off/on\n"
         "  set events 0|1                   node states and EMCYs pushed as they come (mb2co)\n"
         "  info                             what this gateway is\n"
         "  log                              node states and EMCYs since the last log\n"
         "  help [datatype]                  this text, or the data types\n"
         "Answers: [SEQ] OK, [SEQ] VALUE, [SEQ] ERROR:0xABORTCODE #text (SDO abort),\n"
         "[SEQ] ERROR:NNN #text (CiA 309-3 error). INDEX, SUB, NODE: decimal, 0x.. hex\n"
         "or 0.. octal (0x1017, not 1017). '#' starts a comment. A request may be sent\n"
         "before the last answer came: requests to different nodes run at once, the\n"
         "answers come in the order of the requests.\r\n";
}

const char* help_datatype_text() {
  return "\n"
         "b                  boolean, 0 or 1\n"
         "i8 i16 i32 i64     signed integers\n"
         "u8 u16 u32 u64     unsigned integers\n"
         "x8 x16 x32 x64     unsigned integers shown in hex\n"
         "r32 r64            reals\n"
         "vs                 visible string, \"in quotes\" when it has blanks (\"\" is one quote)\n"
         "os us d            octet string, unicode string, domain: base64 on one line\n"
         "hex                bytes as hex pairs, blanks between them optional\r\n";
}

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
