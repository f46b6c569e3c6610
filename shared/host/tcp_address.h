// A TCP endpoint as the Modbus/TCP options write it: mb2co-node --tcp,
// mb2co-plant --tcp, mb2co-master --via-modbus tcp:HOST:PORT. Host-only.
// Only the form is checked here; whether HOST resolves is the socket's
// question (a runtime error, exit 1, not a usage error).
#pragma once
#include <stdint.h>

#include <cctype>
#include <string>

#include "host/status.h"

namespace mb2co {

struct TcpAddress {
  std::string host = "127.0.0.1";  ///< a name or literal, IPv6 without brackets
  uint16_t port = 0;

  /// "127.0.0.1:1502", "[::1]:1502".
  std::string text() const {
    const bool v6 = host.find(':') != std::string::npos;
    return (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
  }
};

/// "HOST:PORT", "[IPV6]:PORT", or a bare "PORT" for 127.0.0.1 (localhost
/// unless told otherwise). PORT 1..65535, or 0 when `allow_zero` (a
/// listener then takes a free port and says which). Failures are one line
/// naming `option`.
inline Status parse_tcp_address(const std::string& option, const std::string& text, bool allow_zero,
                                TcpAddress* out) {
  const std::string form = option + " " + text + ": want HOST:PORT, [IPV6]:PORT or PORT";
  TcpAddress a;
  std::string port = text;
  if (!text.empty() && text[0] == '[') {
    const size_t close = text.find(']');
    if (close == std::string::npos || close + 1 >= text.size() || text[close + 1] != ':' || close == 1)
      return Status::failure(form);
    a.host = text.substr(1, close - 1);
    port = text.substr(close + 2);
  } else if (text.find(':') != std::string::npos) {
    const size_t colon = text.rfind(':');
    a.host = text.substr(0, colon);
    port = text.substr(colon + 1);
    if (a.host.empty() || a.host.find(':') != std::string::npos) return Status::failure(form);
  }
  if (port.empty() || port.size() > 5) return Status::failure(form);
  uint32_t value = 0;
  for (char c : port) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return Status::failure(form);
    value = value * 10u + static_cast<uint32_t>(c - '0');
  }
  if (value > 65535u || (value == 0u && !allow_zero))
    return Status::failure(option + " " + text + ": port " + port + " is outside " +
                           (allow_zero ? "0" : "1") + "..65535");
  a.port = static_cast<uint16_t>(value);
  *out = a;
  return Status::ok();
}

}  // namespace mb2co
