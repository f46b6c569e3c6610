// mb2co-node: the gateway firmware (the same shared/gateway code as on the
// Uno) on Linux: SocketCAN, a pty or tty for Modbus/RTU, buttons and LEDs on
// a line protocol over stdin/stdout. One thread, one poll() loop that plays
// the Arduino's loop(), but sleeps until the next deadline of the gateway
// (Gateway::next_deadline) or an input instead of spinning: under a bus
// flood the CPU goes to frames, not to idle passes.
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "control_channel.h"
#include "eeprom_file.h"
#include "gateway/gateway.h"
#include "host/can_log_file.h"
#include "modbus_tcp_server.h"
#include "node_options.h"
#include "platform/serial_port.h"
#include "platform/socketcan_port.h"
#include "platform/stop_signal.h"
#include "program_data.h"
#include "traced_can.h"

namespace {

bool serial_write(void* ctx, const uint8_t* data, uint16_t n) {
  return static_cast<mb2co::port::SerialPort*>(ctx)->write(data, n).is_ok();
}

bool can_discard(void*, const mb2co::CanFrame&) {
  return true;
}

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

int fail(const std::string& what) {
  std::fprintf(stderr, "mb2co-node: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mb2co;
  const cli::Parsed parsed = cli::parse(node::program(), argc, argv);
  const int early = cli::finish_early(node::program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  node::NodeOptions opt;
  const Status applied = node::apply_options(parsed.args, &opt);
  if (!applied) {
    std::fprintf(stderr, "mb2co-node: %s\n", applied.message().c_str());
    return cli::kExitUsage;
  }

  // Signals from here on end the loop below, so that the pty link goes away.
  const int stop_fd = port::stop_signal_fd();
  if (stop_fd < 0) return fail(std::string("pipe: ") + std::strerror(errno));
  port::ignore_broken_pipes();

  // A parameter file it could never save to is refused before anything is
  // opened or created (no pty link, no CAN socket).
  node::EepromFile eeprom(opt.eeprom, opt.eeprom_write_us);
  if (!opt.eeprom.empty()) {
    const Status usable = eeprom.usable();
    if (!usable) return fail(usable.message());
  }
  // So is a trace file it cannot create (created here, empty when nothing
  // crossed the bus; with --can none nothing does).
  CanLogFile trace;
  if (!opt.trace_can.empty()) {
    const Status created = trace.open(opt.trace_can, opt.can);
    if (!created) return fail("--trace-can " + created.message());
  }

  port::SerialPort serial;
  const bool with_serial = opt.serial != node::kNoSerial;  // else Modbus/TCP only
  const Status opened = !with_serial          ? Status::ok()
                        : !opt.serial.empty() ? serial.open_tty(opt.serial, opt.baud, opt.parity)
                                              : serial.create_pty(opt.pty_link);
  if (!opened) return fail(opened.message());
  linux_port::SocketCanPort can;
  node::TracedCan traced_can(can, trace);
  const bool with_can = opt.can != "none";
  if (with_can) {
    Status bound = can.open(opt.can.c_str());
    if (bound) bound = can.accept_all();
    if (!bound) return fail(bound.message());
  }

  canopen::ParamStorage storage = eeprom.storage();
  // Queued: a pass's frames (a block upload's sub-block) leave together at
  // its end (can.flush() below), kBatch per system call.
  const CanSink can_sink = !with_can         ? CanSink{&can_discard, nullptr}
                           : trace.is_open() ? traced_can.sink()
                                             : can.queue_sink();
  gateway::GatewayPorts ports{can_sink, modbus::ByteSink{&serial_write, &serial},
                              opt.eeprom.empty() ? nullptr : &storage, opt.baud};
  // Kernel filters from the gateway's acceptance ranges (a flood of other
  // frames never reaches the loop): the core sets them at every reset.
  if (with_can) {
    ports.can_control = trace.is_open() ? &node::TracedCan::kControl : &linux_port::SocketCanPort::kControl;
  }
  static gateway::Gateway gw(ports);  // static like on the Uno (and large)
  node::ControlChannel control(gw);
  // 1F50h/1: a large DOMAIN for segmented and block SDO transfers (program_data.h).
  static node::ProgramData program_data;
  static const canopen::SdoDomain program_data_table = program_data.table();
  gw.node().sdo_server().set_domain(&program_data_table);
  gw.node().sdo_server().set_block_transfer(true);
  // Modbus/TCP in front of the same slave (modbus_tcp_server.h).
  node::ModbusTcpServer tcp(gw.modbus_slave());
  if (opt.tcp_given) {
    const Status listening = tcp.listen(opt.tcp, opt.tcp_clients);
    if (!listening) return fail(listening.message());
  }

  gw.start(port::monotonic_us(), opt.node_id);
  if (gw.node().storage_damage_count() != 0) {
    std::fprintf(
        stderr, "mb2co-node: warning: %s: %s\n", opt.eeprom.c_str(),
        gw.node().params_loaded()
            ? "a damaged parameter slot was found, the newest valid set is in force (it may be the older one)"
            : "the saved parameters are damaged, defaults are in force");
  }
  // Command-line settings are written like a technician would over SDO,
  // then take effect by a reset of communication.
  canopen::ObjectDictionary& od = gw.od();
  bool reconfigured = false;
  auto set = [&](uint8_t sub, uint32_t v, uint16_t size) {
    uint8_t b[4];
    canopen::put_le32(b, v);
    if (od.write(0x2000, sub, b, size) != canopen::kSdoOk) return false;
    reconfigured = true;
    return true;
  };
  if (opt.bitrate_kbit && !set(2, opt.bitrate_kbit, 2)) return fail("bit rate refused");
  if (opt.topology >= 0 && !set(3, static_cast<uint32_t>(opt.topology), 1)) return fail("topology refused");
  if (opt.stations && !set(4, opt.stations, 1)) return fail("station count refused");
  if (reconfigured) gw.node().request_reset(canopen::kResetCommunication);

  // "ready" once the Modbus slave accepts frames: after power-up it first
  // waits for t3.5 of silence on the line (serial line spec, initial state),
  // and a request sent before that would be dropped.
  std::string ready = "ready node=" + std::to_string(gw.node_id()) + " can=" + opt.can +
                      " serial=" + (with_serial ? serial.path() : opt.serial) +
                      (serial.link_path().empty() ? "" : " link=" + serial.link_path()) +
                      (tcp.listening() ? " tcp=" + tcp.address().text() : "") + "\n";

  std::string input;
  bool stdin_open = true;
  uint32_t wait_us = 0;  // until the earliest deadline the last pass saw
  while (!control.quit()) {
    pollfd fds[4 + node::ModbusTcpServer::kMaxPollFds] = {{serial.fd(), POLLIN, 0},
                                                          {stop_fd, POLLIN, 0},
                                                          {stdin_open ? 0 : -1, POLLIN, 0},
                                                          {with_can ? can.fd() : -1, POLLIN, 0}};
    const size_t tcp_fds = tcp.poll_fds(fds + 4);
    const timespec wait = as_timespec(wait_us);
    if (ppoll(fds, 4 + tcp_fds, &wait, nullptr) < 0 && errno != EINTR)
      return fail(std::string("poll: ") + std::strerror(errno));
    if (fds[1].revents & POLLIN) break;  // SIGINT / SIGTERM: clean exit
    // Taken before the serial port is found empty, as modbus/slave.h asks:
    // no byte that arrived before `now` is left unread when process(now) runs.
    const uint32_t now = port::monotonic_us();
    if (fds[0].revents & (POLLIN | POLLERR | POLLHUP)) {
      uint8_t bytes[256];
      uint32_t stamps[256];
      size_t n = 0;
      const Status got = serial.read(bytes, stamps, sizeof bytes, &n);
      if (!got) return fail(got.message());
      for (size_t i = 0; i < n; ++i) gw.on_serial_byte(bytes[i], stamps[i]);
    }
    if (fds[2].revents & (POLLIN | POLLHUP)) {
      char buf[512];
      const ssize_t r = read(0, buf, sizeof buf);
      if (r <= 0) {
        stdin_open = false;  // no more commands; keep running until a signal
      } else {
        input.append(buf, static_cast<size_t>(r));
        for (size_t nl; (nl = input.find('\n')) != std::string::npos;) {
          const std::string reply = control.handle(input.substr(0, nl), now);
          input.erase(0, nl + 1);
          if (!reply.empty()) say(reply + "\n");
        }
      }
    }
    // Timers first: a heartbeat due now leaves before this pass's frames
    // (each may cost a send), whatever the bus carries.
    control.process(now);
    say(control.events(gw.process(now, control.buttons()), now));
    tcp.handle(fds + 4, tcp_fds);  // after process(): FC 2Bh/0Dh runs with its `now`
    // Then at most kMaxFramesPerPass frames. What they make due (an answer
    // to a Modbus request, a state line) runs in the next pass, at once.
    bool frames_taken = false;
    if (fds[3].revents & POLLIN) {
      linux_port::TimedCanFrame frames[kMaxFramesPerPass];
      const size_t got = can.receive(frames, kMaxFramesPerPass);
      for (size_t i = 0; i < got; ++i) {
        traced_can.received(frames[i].frame);
        gw.on_can_frame(frames[i].frame, static_cast<uint32_t>(frames[i].rx_time_us));
      }
      frames_taken = got != 0;
    }
    can.flush();         // what the pass sent, in order
    traced_can.flush();  // whole lines for a reader of the trace (nothing when none)
    uint32_t modbus_deadline_us = 0;
    if (!ready.empty() && !gw.modbus_slave().deadline(modbus_deadline_us)) {
      say(ready);
      ready.clear();
    }
    // Sleep until something is due; after frames not at all: what they
    // made due (Gateway::next_deadline holds only after a process() that
    // saw them) runs in the next pass, as do frames a capped pass left.
    wait_us = 0;
    if (!frames_taken) {
      NextDeadline due(now);
      uint32_t at_us = 0;
      if (gw.next_deadline(now, &at_us)) due.at(at_us);
      control.next_deadline(due);
      due.in(kLongestWaitUs);
      if (can.queued() != 0) due.in(kRetrySendUs);  // the kernel had no room: again soon
      due.result(&at_us);
      wait_us = time_until(port::monotonic_us(), at_us);
    }
  }
  // A clean exit keeps an answered save: its remaining passes first.
  while (gw.node().saving()) gw.process(port::monotonic_us(), control.buttons());
  can.flush();
  serial.close();
  can.close();
  trace.close();
  if (trace.write_errors() != 0)
    return fail("--trace-can " + opt.trace_can + ": write failed, the trace is incomplete");
  return 0;
}
