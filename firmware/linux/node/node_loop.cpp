#include "node_loop.h"

#include <errno.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include "platform/stop_signal.h"

namespace mb2co {
namespace node {

namespace {

// Control-channel output: whole lines, flushed at once (tests wait for them).
void say(const std::string& lines) {
  if (lines.empty()) return;
  std::fputs(lines.c_str(), stdout);
  std::fflush(stdout);
}

// Longest sleep of the loop: only a guard, the deadlines bound every wait.
constexpr uint32_t kLongestWaitUs = 1000000;
// Frames handed in per loop pass at most. A pass runs the due timers
// (heartbeat, TPDO timers, SDO timeouts) before its frames, so a timer
// waits at most for one pass's frames, each of which may cost a send (an
// SDO answer): a system call costs 16-100 us under user-mode Linux on an
// idle host and far more on a busy one (16 frames a pass let a heartbeat
// come 18 ms late there, node.sdo_flood; 4 cost the test's flooder its CPU:
// docs/performance.md), microseconds on a real host. The rest wait in the
// socket for the next pass, which polls without sleeping.
constexpr size_t kMaxFramesPerPass = 8;
// Longest sleep while frames the kernel had no room for wait to be sent.
constexpr uint32_t kRetrySendUs = 1000;

timespec as_timespec(uint32_t us) {
  return timespec{static_cast<time_t>(us / 1000000u), static_cast<long>(us % 1000000u) * 1000L};
}

}  // namespace

NodeLoop::NodeLoop(const NodeOptions& opt, gateway::Gateway& gw, ControlChannel& control,
                   ModbusTcpServer& tcp, NodeWiring& wiring, int stop_fd)
    : opt_(opt), gw_(gw), control_(control), tcp_(tcp), wiring_(wiring), stop_fd_(stop_fd) {
  // "ready" once the Modbus slave accepts frames: after power-up it first
  // waits for t3.5 of silence on the line (serial line spec, initial state),
  // and a request sent before that would be dropped.
  const port::SerialPort& serial = wiring.serial;
  ready_ = "ready node=" + std::to_string(gw.node_id()) + " can=" + opt.can +
           " serial=" + wiring.serial_text(opt) +
           (serial.link_path().empty() ? "" : " link=" + serial.link_path()) +
           (tcp.listening() ? " tcp=" + tcp.address().text() : "") + "\n";
}

Status NodeLoop::run() {
  uint32_t wait_us = 0;  // until the earliest deadline the last pass saw
  while (!control_.quit()) {
    pollfd fds[kFds] = {{wiring_.serial.fd(), POLLIN, 0},
                        {stop_fd_, POLLIN, 0},
                        {stdin_open_ ? 0 : -1, POLLIN, 0},
                        {wiring_.with_can ? wiring_.can.fd() : -1, POLLIN, 0}};
    const size_t tcp_fds = tcp_.poll_fds(fds + 4);
    const timespec wait = as_timespec(wait_us);
    if (ppoll(fds, 4 + tcp_fds, &wait, nullptr) < 0 && errno != EINTR)
      return Status::failure(std::string("poll: ") + std::strerror(errno));
    if (fds[1].revents & POLLIN) break;  // SIGINT / SIGTERM: clean exit
    // Taken before the serial port is found empty, as modbus/slave.h asks:
    // no byte that arrived before `now` is left unread when process(now) runs.
    const uint32_t now = port::monotonic_us();
    bool frames_taken = false;
    Status passed = pass(fds, tcp_fds, now, &frames_taken);
    if (!passed) return passed;
    // Sleep until something is due; after frames not at all: what they
    // made due (Gateway::next_deadline holds only after a process() that
    // saw them) runs in the next pass, as do frames a capped pass left.
    wait_us = frames_taken ? 0 : sleep_us(now);
  }
  return Status::ok();
}

Status NodeLoop::pass(pollfd* fds, size_t tcp_fds, uint32_t now, bool* frames_taken) {
  if (fds[0].revents & (POLLIN | POLLERR | POLLHUP)) {
    uint8_t bytes[256];
    uint32_t stamps[256];
    size_t n = 0;
    Status got = wiring_.serial.read(bytes, stamps, sizeof bytes, &n);
    if (!got) return got;
    for (size_t i = 0; i < n; ++i) gw_.on_serial_byte(bytes[i], stamps[i]);
  }
  if (fds[2].revents & (POLLIN | POLLHUP)) take_commands(now);
  // Timers first: a heartbeat due now leaves before this pass's frames
  // (each may cost a send), whatever the bus carries.
  control_.process(now);
  say(control_.events(gw_.process(now, control_.buttons()), now));
  tcp_.handle(fds + 4, tcp_fds);  // after process(): FC 2Bh/0Dh runs with its `now`
  // Then at most kMaxFramesPerPass frames. What they make due (an answer
  // to a Modbus request, a state line) runs in the next pass, at once.
  *frames_taken = take_frames(fds);
  wiring_.can.flush();         // what the pass sent, in order
  wiring_.traced_can.flush();  // whole lines for a reader of the trace (nothing when none)
  say_ready();
  return Status::ok();
}

void NodeLoop::take_commands(uint32_t now) {
  char buf[512];
  const ssize_t r = read(0, buf, sizeof buf);
  if (r <= 0) {
    stdin_open_ = false;  // no more commands; keep running until a signal
    return;
  }
  input_.append(buf, static_cast<size_t>(r));
  for (size_t nl; (nl = input_.find('\n')) != std::string::npos;) {
    const std::string reply = control_.handle(input_.substr(0, nl), now);
    input_.erase(0, nl + 1);
    if (!reply.empty()) say(reply + "\n");
  }
}

bool NodeLoop::take_frames(const pollfd* fds) {
  if (!(fds[3].revents & POLLIN)) return false;
  linux_port::TimedCanFrame frames[kMaxFramesPerPass];
  const size_t got = wiring_.can.receive(frames, kMaxFramesPerPass);
  for (size_t i = 0; i < got; ++i) {
    wiring_.traced_can.received(frames[i].frame);
    gw_.on_can_frame(frames[i].frame, static_cast<uint32_t>(frames[i].rx_time_us));
  }
  return got != 0;
}

void NodeLoop::say_ready() {
  uint32_t modbus_deadline_us = 0;
  if (!ready_.empty() && !gw_.modbus_slave().deadline(modbus_deadline_us)) {
    say(ready_);
    ready_.clear();
  }
}

uint32_t NodeLoop::sleep_us(uint32_t now) const {
  NextDeadline due(now);
  uint32_t at_us = 0;
  if (gw_.next_deadline(now, &at_us)) due.at(at_us);
  control_.next_deadline(due);
  due.in(kLongestWaitUs);
  if (wiring_.can.queued() != 0) due.in(kRetrySendUs);  // the kernel had no room: again soon
  due.result(&at_us);
  return time_until(port::monotonic_us(), at_us);
}

Status NodeLoop::finish() {
  while (gw_.node().saving()) gw_.process(port::monotonic_us(), control_.buttons());
  wiring_.can.flush();
  wiring_.serial.close();
  wiring_.can.close();
  wiring_.trace.close();
  if (wiring_.trace.write_errors() != 0)
    return Status::failure("--trace-can " + opt_.trace_can + ": write failed, the trace is incomplete");
  return Status::ok();
}

}  // namespace node
}  // namespace mb2co
