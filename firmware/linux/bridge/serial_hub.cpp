// mb2co-serial-hub: a multi-drop serial line out of pseudo-terminals, so a
// serial CANopen segment runs without RS-485 hardware (docs/serial-canopen.md,
// "Try it"). Every byte one member writes is read by all the others, not by
// itself, as on RS-485 without echo; a member named +LINK also reads its own
// bytes back (an echoing adapter, for mb2co-bridge --echo), @PATH joins an
// existing terminal (mb2co-uno's pty) instead of making one. It makes one pty
// per LINK (a symlink to its slave side, raw mode), prints "ready" and relays
// until SIGINT/SIGTERM; it keeps every slave side open, so members may come
// and go. Byte timing is the host's: the ptys have no baud rate.
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "host/cli.h"
#include "stop_signal.h"

namespace {

using namespace mb2co;

constexpr size_t kMostMembers = 32;

struct Member {
  int fd = -1;        ///< the side the hub reads and writes
  bool echo = false;  ///< reads its own bytes back
  std::string link;   ///< symlink made for it ("" for @PATH)
};

cli::Program make_program() {
  cli::Program p;
  p.name = "mb2co-serial-hub";
  p.description =
      "A multi-drop serial line of pseudo-terminals (RS-485 without hardware): every byte a member\n"
      "writes, the other members read. MEMBER: LINK (a new pty, LINK a symlink to it), +LINK (one\n"
      "that also reads its own bytes: an echoing adapter), @PATH (an existing terminal joins).\n"
      "Prints \"ready\" once every member is there.\n";
  cli::Command c;
  c.operands = "MEMBER MEMBER [MEMBER]...";
  c.min_operands = 2;  // a line of one member carries nothing
  c.max_operands = kMostMembers;
  p.commands = {c};
  p.footer = "\nexit status: 0 on SIGINT/SIGTERM, 1 runtime error, 2 usage error\n";
  return p;
}

int fail(const std::string& what, int code) {
  std::fprintf(stderr, "mb2co-serial-hub: %s\n", what.c_str());
  return code;
}

void make_raw(int fd) {
  termios t{};
  if (tcgetattr(fd, &t) != 0) return;
  cfmakeraw(&t);
  tcsetattr(fd, TCSANOW, &t);
}

/// Opens or makes one member; "" or why not.
std::string open_member(std::string spec, Member* m, std::vector<int>* keep) {
  if (!spec.empty() && spec[0] == '+') {
    m->echo = true;
    spec.erase(0, 1);
  }
  if (spec.empty()) return "empty MEMBER";
  if (spec[0] == '@') {
    m->fd = open(spec.c_str() + 1, O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (m->fd < 0) return spec.substr(1) + ": " + std::strerror(errno);
    make_raw(m->fd);
    return "";
  }
  int master = -1, slave = -1;
  if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0)
    return std::string("openpty: ") + std::strerror(errno);
  make_raw(master);
  make_raw(slave);
  fcntl(master, F_SETFL, fcntl(master, F_GETFL) | O_NONBLOCK);
  const char* name = ttyname(slave);
  unlink(spec.c_str());  // a link left by an earlier run
  if (name == nullptr || symlink(name, spec.c_str()) != 0) return spec + ": " + std::strerror(errno);
  m->fd = master;
  m->link = spec;
  keep->push_back(slave);
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  static const cli::Program program = make_program();
  const cli::Parsed parsed = cli::parse(program, argc, argv);
  const int early = cli::finish_early(program, parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  const std::vector<std::string>& specs = parsed.args.operands;  // 2..kMostMembers (the table)

  bridge::catch_stop_signals();
  std::vector<Member> members(specs.size());
  std::vector<int> keep;
  int code = 0;
  for (size_t i = 0; i < specs.size() && code == 0; ++i) {
    const std::string why = open_member(specs[i], &members[i], &keep);
    if (!why.empty()) code = fail(why, 1);
  }
  if (code == 0) {
    std::printf("ready\n");
    std::fflush(stdout);
  }
  std::vector<pollfd> fds;
  fds.reserve(members.size());
  for (const Member& m : members) fds.push_back(pollfd{m.fd, POLLIN, 0});
  while (code == 0 && !bridge::stop_requested()) {
    if (poll(fds.data(), fds.size(), 200) < 0) {
      if (errno == EINTR) continue;
      code = fail(std::string("poll: ") + std::strerror(errno), 1);
      break;
    }
    for (size_t i = 0; i < fds.size(); ++i) {
      if (!(fds[i].revents & POLLIN)) continue;
      unsigned char buf[4096];
      const ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n <= 0) continue;  // a member that went away: its slave side stays open
      for (size_t j = 0; j < members.size(); ++j)
        if (j != i || members[j].echo) (void)!write(members[j].fd, buf, static_cast<size_t>(n));
    }
  }
  for (const Member& m : members) {
    if (!m.link.empty()) unlink(m.link.c_str());
    if (m.fd >= 0) close(m.fd);
  }
  for (int fd : keep) close(fd);
  return code;
}
