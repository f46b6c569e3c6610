// mb2co-bridge: the smart bridge of shared/serialnet/bridge.h on Linux: a
// serial CANopen segment on a tty or pty, SocketCAN on the other side. One
// thread, one poll() loop that sleeps until a byte, a frame or the bridge's
// next deadline (its polls and windows are timed in CLOCK_MONOTONIC µs).
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>

#include "bridge_options.h"
#include "segment_line.h"
#include "serialnet/bridge.h"
#include "socketcan_port.h"

namespace {

int g_signal_pipe[2] = {-1, -1};

void on_signal(int) {
  const char b = 1;
  const ssize_t n = write(g_signal_pipe[1], &b, 1);
  (void)n;
}

int fail(const std::string& what) {
  std::fprintf(stderr, "mb2co-bridge: %s\n", what.c_str());
  return 1;
}

void to_bridge(void* ctx, uint8_t byte, uint32_t byte_us) {
  static_cast<mb2co::serialnet::Bridge*>(ctx)->on_byte(byte, byte_us);
}

/// Milliseconds poll() may sleep: until the deadline (rounded up), at most 100.
int poll_timeout_ms(const mb2co::serialnet::Bridge& bridge, uint32_t now) {
  mb2co::NextDeadline d(now);
  bridge.next_deadline(d);
  uint32_t at = 0;
  if (!d.result(&at)) return 100;
  const uint32_t wait_us = mb2co::time_until(now, at);
  return wait_us >= 100000u ? 100 : static_cast<int>((wait_us + 999u) / 1000u);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  bridge::BridgeOptions opt;
  Status parsed = bridge::parse_bridge_options(argc, argv, &opt);
  serialnet::BridgeConfig config = {};
  if (parsed && !opt.help && !opt.version) parsed = bridge::bridge_config(opt, &config);
  if (!parsed) {
    std::fprintf(stderr, "mb2co-bridge: %s\n", parsed.message().c_str());
    return 2;
  }
  if (opt.help) {
    std::fputs(bridge::bridge_usage_head(), stdout);
    std::fputs(bridge::segment_usage(), stdout);
    return 0;
  }
  if (opt.version) {
    std::puts("mb2co-bridge 0.1.0");
    return 0;
  }

  if (pipe2(g_signal_pipe, O_CLOEXEC | O_NONBLOCK) != 0)
    return fail(std::string("pipe: ") + std::strerror(errno));
  struct sigaction sa = {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);

  bridge::SegmentLine line;
  const Status opened = line.open(opt.segment);
  if (!opened) return fail(opened.message());
  linux_port::SocketCanPort can;
  Status bound = can.open(opt.can.c_str());
  if (bound) bound = can.accept_all();
  if (!bound) return fail(bound.message());

  static serialnet::Bridge br(config, line.sink(), can.sink());
  std::printf("ready serial=%s can=%s nodes=%d-%d offset=%d access=%s\n", line.port().path().c_str(),
              opt.can.c_str(), opt.segment.first, opt.segment.last, opt.offset,
              opt.segment.token ? "token" : "poll");
  std::fflush(stdout);

  for (;;) {
    pollfd fds[3] = {{line.fd(), POLLIN, 0}, {can.fd(), POLLIN, 0}, {g_signal_pipe[0], POLLIN, 0}};
    const int timeout = poll_timeout_ms(br, port::monotonic_us());
    if (poll(fds, 3, timeout) < 0 && errno != EINTR)
      return fail(std::string("poll: ") + std::strerror(errno));
    if (fds[2].revents & POLLIN) break;
    if (fds[0].revents & (POLLIN | POLLERR | POLLHUP)) {
      const Status got = line.read(&to_bridge, &br);
      if (!got) return fail(got.message());
    }
    if (fds[1].revents & POLLIN) {
      linux_port::TimedCanFrame frames[linux_port::SocketCanPort::kBatch];
      size_t got = 0;
      while ((got = can.receive(frames, linux_port::SocketCanPort::kBatch)) > 0) {
        for (size_t i = 0; i < got; ++i)
          br.on_can(frames[i].frame, static_cast<uint32_t>(frames[i].rx_time_us));
      }
    }
    br.process(port::monotonic_us());
  }
  if (opt.verbose) {
    const serialnet::Bridge::Counters& c = br.counters();
    std::fprintf(stderr,
                 "mb2co-bridge: to_can=%u to_serial=%u polls=%u can_syncs=%u not_consumed=%u unmappable=%u "
                 "overflow=%u echo_dropped=%u\n",
                 c.to_can, c.to_serial, c.polls, c.can_syncs, c.not_consumed, c.unmappable, c.overflow,
                 static_cast<unsigned>(line.echo_bytes_dropped()));
  }
  return 0;
}
