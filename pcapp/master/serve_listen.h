// Where `serve` listens: `unix:PATH` (a local socket, the default, as
// canopend's "local-PATH") or `tcp:HOST:PORT` (`tcp:PORT` is 127.0.0.1:PORT;
// HOST may be [::1]; PORT 0 lets the kernel choose). CiA 309-3 has no
// authentication: whoever reaches the socket commands the network, so the
// local socket is made rw for its owner only and TCP is localhost unless a
// HOST says otherwise.
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"

namespace mb2co {
namespace master {

struct ListenAddress {
  bool tcp = false;
  std::string path;  ///< unix:
  std::string host;  ///< tcp: as given, without brackets
  uint16_t port = 0;
};

/// Checks the text; fails with one line naming what is wrong.
Status parse_listen(const std::string& text, ListenAddress* out);

/// A listening, non-blocking socket. A unix socket file left by a server
/// that is gone is replaced; one a server still answers on, or a file that
/// is no socket, is refused. `*where` is the address as bound ("tcp:127.0.0.1:60000",
/// with the port the kernel chose for 0).
Status open_listener(const ListenAddress& a, int* fd, std::string* where);

/// True when the TCP address only reaches this machine (loopback).
bool loopback_only(const ListenAddress& a);

}  // namespace master
}  // namespace mb2co
