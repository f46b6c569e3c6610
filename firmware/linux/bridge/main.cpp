// mb2co-bridge: the smart bridge of shared/serialnet/bridge.h on Linux: a
// serial CANopen segment on a tty or pty, SocketCAN on the other side. One
// thread, one poll() loop that sleeps until a byte, a frame or the bridge's
// next deadline (its polls and windows are timed in CLOCK_MONOTONIC µs).
#include <errno.h>
#include <poll.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "bridge_options.h"
#include "platform/socketcan_port.h"
#include "platform/stop_signal.h"
#include "segment_line.h"
#include "serialnet/bridge.h"

namespace {

int fail(const std::string& what) {
  std::fprintf(stderr, "mb2co-bridge: %s\n", what.c_str());
  return 1;
}

void to_bridge(void* ctx, uint8_t byte, uint32_t byte_us) {
  static_cast<mb2co::serialnet::Bridge*>(ctx)->on_byte(byte, byte_us);
}

int poll_timeout_ms(const mb2co::serialnet::Bridge& bridge, uint32_t now) {
  mb2co::NextDeadline d(now);
  bridge.next_deadline(d);
  return mb2co::port::poll_timeout_ms(d);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  const cli::Parsed parsed = cli::parse(bridge::bridge_program(), argc, argv);
  const int early = cli::finish_early(bridge::bridge_program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  bridge::BridgeOptions opt;
  serialnet::BridgeConfig config = {};
  Status usable = bridge::apply_bridge_options(parsed.args, &opt);
  if (usable) usable = bridge::bridge_config(opt, &config);
  if (!usable) {
    std::fprintf(stderr, "mb2co-bridge: %s\n", usable.message().c_str());
    return cli::kExitUsage;
  }

  port::catch_stop_signals();
  port::ignore_broken_pipes();
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

  while (!port::stop_requested()) {
    pollfd fds[2] = {{line.fd(), POLLIN, 0}, {can.fd(), POLLIN, 0}};
    if (poll(fds, 2, poll_timeout_ms(br, port::monotonic_us())) < 0) {
      if (errno == EINTR) continue;
      return fail(std::string("poll: ") + std::strerror(errno));
    }
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
