#include "serve_listen.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "host/tcp_address.h"

namespace mb2co {
namespace master {

namespace {

const int kBacklog = 16;

std::string error_text(const std::string& what) {
  return what + ": " + strerror(errno);
}

/// A unix socket file: replaced when nobody answers on it any more.
Status clear_stale_socket(const std::string& path) {
  struct stat st;
  if (lstat(path.c_str(), &st) != 0) return Status::ok();  // nothing there
  if (!S_ISSOCK(st.st_mode)) return Status::failure(path + " exists and is not a socket: not replaced");
  const int probe = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (probe < 0) return Status::failure(error_text("socket"));
  sockaddr_un addr = {};
  addr.sun_family = AF_UNIX;
  memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const bool answered = connect(probe, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  close(probe);
  if (answered) return Status::failure(path + " is in use: another server answers on it");
  if (unlink(path.c_str()) != 0) return Status::failure(error_text("cannot replace " + path));
  return Status::ok();
}

Status open_unix(const ListenAddress& a, int* fd, std::string* where) {
  Status cleared = clear_stale_socket(a.path);
  if (!cleared) return cleared;
  const int s = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (s < 0) return Status::failure(error_text("socket"));
  sockaddr_un addr = {};
  addr.sun_family = AF_UNIX;
  memcpy(addr.sun_path, a.path.c_str(), a.path.size() + 1);
  // Owner only from the start: the file never exists with wider rights.
  const mode_t old = umask(0177);
  const int bound = bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  umask(old);
  if (bound != 0 || listen(s, kBacklog) != 0) {
    Status failed = Status::failure(error_text("cannot listen on unix:" + a.path));
    close(s);
    return failed;
  }
  *fd = s;
  *where = "unix:" + a.path;
  return Status::ok();
}

Status open_tcp(const ListenAddress& a, int* fd, std::string* where) {
  addrinfo hints = {};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const int rc = getaddrinfo(a.host.c_str(), std::to_string(a.port).c_str(), &hints, &found);
  if (rc != 0) return Status::failure("tcp:" + a.host + ": " + gai_strerror(rc));
  Status result = Status::failure("tcp:" + a.host + ": no address to listen on");
  for (addrinfo* ai = found; ai != nullptr; ai = ai->ai_next) {
    const int s = socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai->ai_protocol);
    if (s < 0) continue;
    const int on = 1;
    setsockopt(s, SOL_SOCKET, SO_REUSEADDR, &on, sizeof on);
    if (bind(s, ai->ai_addr, ai->ai_addrlen) != 0 || listen(s, kBacklog) != 0) {
      result = Status::failure(error_text("cannot listen on tcp:" + a.host + ":" + std::to_string(a.port)));
      close(s);
      continue;
    }
    sockaddr_storage bound = {};
    socklen_t len = sizeof bound;
    getsockname(s, reinterpret_cast<sockaddr*>(&bound), &len);
    char host[INET6_ADDRSTRLEN] = "?";
    uint16_t port = a.port;
    if (bound.ss_family == AF_INET6) {
      const auto* in6 = reinterpret_cast<const sockaddr_in6*>(&bound);
      inet_ntop(AF_INET6, &in6->sin6_addr, host, sizeof host);
      port = ntohs(in6->sin6_port);
      *where = std::string("tcp:[") + host + "]:" + std::to_string(port);
    } else {
      const auto* in4 = reinterpret_cast<const sockaddr_in*>(&bound);
      inet_ntop(AF_INET, &in4->sin_addr, host, sizeof host);
      port = ntohs(in4->sin_port);
      *where = std::string("tcp:") + host + ":" + std::to_string(port);
    }
    *fd = s;
    result = Status::ok();
    break;
  }
  freeaddrinfo(found);
  return result;
}

}  // namespace

Status parse_listen(const std::string& text, ListenAddress* out) {
  const std::string usage = "--listen wants unix:PATH or tcp:[HOST:]PORT, got \"" + text + "\"";
  ListenAddress a;
  if (text.compare(0, 5, "unix:") == 0) {
    a.path = text.substr(5);
    if (a.path.empty()) return Status::failure(usage);
    if (a.path.size() >= sizeof(sockaddr_un{}.sun_path))
      return Status::failure("--listen unix:PATH: the path is longer than " +
                             std::to_string(sizeof(sockaddr_un{}.sun_path) - 1) + " bytes");
    *out = a;
    return Status::ok();
  }
  if (text.compare(0, 4, "tcp:") != 0) return Status::failure(usage);
  // The form every mb2co program's TCP option takes (host/tcp_address.h).
  TcpAddress tcp;
  Status s = parse_tcp_address("--listen tcp:", text.substr(4), true, &tcp);
  if (!s) return s;
  a.tcp = true;
  a.host = tcp.host;
  a.port = tcp.port;
  *out = a;
  return Status::ok();
}

Status open_listener(const ListenAddress& a, int* fd, std::string* where) {
  return a.tcp ? open_tcp(a, fd, where) : open_unix(a, fd, where);
}

bool loopback_only(const ListenAddress& a) {
  if (!a.tcp) return true;
  if (a.host == "localhost" || a.host == "::1") return true;
  in_addr v4;
  return inet_pton(AF_INET, a.host.c_str(), &v4) == 1 && (ntohl(v4.s_addr) >> 24) == 127;
}

}  // namespace master
}  // namespace mb2co
