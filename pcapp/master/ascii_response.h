// The answers of CiA 309-3's ASCII mapping as CANopenNode's gateway writes
// them: one line per request, ended by CR LF, starting with the request's
// sequence number in brackets:
//
//   [7] OK                                   done
//   [7] 1000                                 a value read
//   [7] ERROR:0x06020000 #object does not exist in the object dictionary
//   [7] ERROR:101 #Syntax error.
//
// An SDO abort is its 32-bit code in hex, named as CiA 301 names it
// (abort_text.h); any other failure is a CiA 309-3 "internal error code",
// in decimal, with CANopenNode's description. Plain C++ without OS or Qt.
#pragma once
#include <stdint.h>

#include <string>

namespace mb2co {
namespace master {
namespace ascii {

/// CiA 309-3's internal error codes (CANopenNode's CO_GTWA_respErrorCode_t);
/// those mb2co answers with, and the rest for completeness.
enum class GatewayError : uint16_t {
  kNone = 0,
  kRequestNotSupported = 100,  ///< a command we do not have (LSS, led, ...)
  kSyntax = 101,               ///< the line does not parse, a value out of its type's range
  kInternalState = 102,        ///< the frame or the gateway request could not go out
  kTimeOut = 103,
  kNoDefaultNet = 104,
  kNoDefaultNode = 105,  ///< no NODE in the line and no `set node` before
  kUnsupportedNet = 106,
  kUnsupportedNode = 107,  ///< NODE above 127 (or 0 where not NMT)
  kLostGuarding = 200,
  kLostConnection = 201,
  kHeartbeatStarted = 202,
  kHeartbeatLost = 203,
  kWrongNmtState = 204,
  kBootUp = 205,
  kErrorPassive = 300,
  kBusOff = 301,
  kCanOverflow = 303,
  kCanInit = 304,
  kCanActive = 305,
  kPdoAlreadyUsed = 400,
  kPdoLengthExceeded = 401,
  kOutOfMemory = 600,  ///< a line or a value longer than the gateway takes
};

/// CANopenNode's description ("Syntax error."); "-" for another number.
const char* gateway_error_text(GatewayError e);

/// "[seq] OK\r\n"
std::string ok_line(uint32_t seq);
/// "[seq] TEXT\r\n"
std::string value_line(uint32_t seq, const std::string& text);
/// "[seq] ERROR:101 #Syntax error.\r\n"
std::string error_line(uint32_t seq, GatewayError e);
/// "[seq] ERROR:0x06020000 #object does not exist in the object dictionary\r\n"
std::string abort_line(uint32_t seq, uint32_t abort_code);

/// The answer to `help` and to `help datatype`: lines ended by LF, the last
/// by CR LF, without a sequence number (as CANopenNode's).
const char* help_text();
const char* help_datatype_text();

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
