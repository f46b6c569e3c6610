// mb2co-uno: the Uno's gateway image (the very mb2co-gateway.elf that is
// flashed; or the I/O node's, --image ionode) in libsimavr, paced to real
// time, with USART0 on a pty, the
// MCP2515 shield on SocketCAN and the operator panel on stdin/stdout
// (docs/uno-sim.md). One thread, in passes of up to 2 ms of simulated time:
// run the simulation up to 2 ms ahead of the wall clock, move what the pass
// produced out in one call per kind, read the clock once, wait in one poll()
// for input or the clock and take what came in one read per input
// (io_counts.h: the system calls a pass makes, which user-mode Linux traps).
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <iostream>
#include <string>
#include <vector>

#include "eeprom_image.h"
#include "host/candump_text.h"
#include "io_counts.h"
#include "pacer.h"
#include "platform/serial_port.h"
#include "platform/socketcan_port.h"
#include "platform/stop_signal.h"
#include "uno_options.h"
#include "uno_rig.h"

namespace {

using namespace mb2co;

uint64_t wall_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

int fail(const std::string& what) {
  fprintf(stderr, "mb2co-uno: %s\n", what.c_str());
  return 1;
}

// Control-channel output: whole lines, flushed at once (tests wait for them).
void say(const std::string& line) {
  fputs(line.c_str(), stdout);
  fputc('\n', stdout);
  fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const cli::Parsed parsed = cli::parse(uno::program(), argc, argv);
  const int early = cli::finish_early(uno::program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  uno::UnoOptions opt;
  uno::apply_options(parsed.args, &opt);
  const uno::UnoImage& image = *uno::find_image(opt.image);  // the parser checked the name
  if (opt.elf.empty()) opt.elf = std::string(MB2CO_UNO_AVR_DIR) + "/" + image.elf;

  const int stop_fd = port::stop_signal_fd();
  if (stop_fd < 0) return fail(std::string("pipe: ") + strerror(errno));
  port::ignore_broken_pipes();

  static uno::UnoRig rig(image);  // large; static like the image's own globals
  const Status loaded = rig.load(opt.elf);
  if (!loaded) return fail(loaded.message());
  uno::EepromImage eeprom(opt.eeprom);
  if (!opt.eeprom.empty()) {
    const Status read = eeprom.load();
    if (!read) return fail(read.message());
    rig.board().set_eeprom(eeprom.bytes(), eeprom.size());
  }
  linux_port::SocketCanPort can;
  const bool with_can = opt.can != "none";
  if (with_can) {
    Status bound = can.open(opt.can.c_str());
    if (bound) bound = can.accept_all();
    if (!bound) return fail(bound.message());
  }
  port::SerialPort serial;
  const Status opened = serial.create_pty(opt.pty_link);
  if (!opened) return fail(opened.message());

  const uint64_t wall_start = wall_us();
  uno::Pacer pacer(!opt.unpaced, wall_start, 0);
  auto at_us = [&](uint64_t sim_us) { return static_cast<uint32_t>(pacer.wall_of(sim_us)); };
  const uint64_t end_us = opt.duration_ms ? uint64_t{opt.duration_ms} * 1000u : UINT64_MAX;
  // A "leds" line for each change of what the five LEDs show (the image
  // rewrites pins with the level they have: no line for that).
  std::string leds_shown;
  auto show_leds = [&](uint64_t sim_us) {
    const std::string line = rig.panel().leds_line(at_us(sim_us));
    const std::string levels = line.substr(0, line.rfind(" at_us="));
    if (levels == leds_shown) return;
    leds_shown = levels;
    say(line);
  };
  show_leds(0);

  bool ready_said = false;
  bool stdin_open = true;
  bool stop = false;
  std::string input;
  int exit_code = 0;
  uno::IoCounts io;

  // Every input with something waiting, one read each (CAN: again while a
  // batch comes back full); false on a failure (exit_code set).
  auto take_input = [&](const pollfd* fds) {
    if (fds[1].revents & POLLIN) stop = true;  // SIGINT / SIGTERM: clean exit
    if (fds[0].revents & (POLLIN | POLLERR | POLLHUP)) {
      uint8_t bytes[256];
      uint32_t stamps[256];
      size_t n = 0;
      ++io.reads;
      const Status got = serial.read(bytes, stamps, sizeof bytes, &n);
      if (!got) {
        exit_code = fail(got.message());
        return false;
      }
      rig.serial_in(bytes, n);
    }
    if (fds[3].revents & POLLIN) {
      linux_port::TimedCanFrame frames[linux_port::SocketCanPort::kBatch];
      size_t got = 0;
      do {
        ++io.reads;
        got = can.receive(frames, linux_port::SocketCanPort::kBatch);
        // A batch's kernel stamps are wall-clock time: the port reads both
        // clocks once to move them onto the monotonic one.
        if (got > 0) io.clock_reads += 2;
        io.can_frames_in += got;
        // At the kernel's receive time: a backlog read after the host held
        // us up keeps its spacing (a burst would overrun the chip's buffers).
        for (size_t i = 0; i < got; ++i) rig.can_in(frames[i].frame, pacer.sim_of(frames[i].rx_time_us));
      } while (got == linux_port::SocketCanPort::kBatch);
    }
    if (fds[2].revents & (POLLIN | POLLHUP)) {
      char buf[512];
      ++io.reads;
      const ssize_t r = read(0, buf, sizeof buf);
      if (r <= 0) {
        stdin_open = false;  // no more commands; run on until a signal
      } else {
        input.append(buf, static_cast<size_t>(r));
      }
    }
    return true;
  };
  // Polls every input, waiting up to `wait_us`; the number ready (-1:
  // failed, exit_code set; 0 also when a signal cut the wait short, then
  // `*cut` is set).
  auto poll_inputs = [&](pollfd* fds, uint64_t wait_us, bool* cut) {
    fds[0] = {serial.fd(), POLLIN, 0};
    fds[1] = {stop_fd, POLLIN, 0};
    fds[2] = {stdin_open ? 0 : -1, POLLIN, 0};
    fds[3] = {with_can ? can.fd() : -1, POLLIN, 0};
    const timespec timeout{static_cast<time_t>(wait_us / 1000000u),
                           static_cast<long>(wait_us % 1000000u) * 1000};
    ++io.polls;
    const int ready = ppoll(fds, 4, &timeout, nullptr);
    if (ready >= 0) return ready;
    if (errno == EINTR) {
      *cut = true;
      return 0;
    }
    exit_code = fail(std::string("poll: ") + strerror(errno));
    return -1;
  };

  // The wall clock as last read, or a moment known to have passed since:
  // one reading per pass, after the run. Under user-mode Linux (the vcan
  // tests, hil/live) clock_gettime() is a trapped system call (~15 us of its
  // one CPU), not the vDSO's 20 ns; unpaced, nothing needs it.
  // The pacer never sees a time later than the true one, so its lead holds.
  uint64_t wall_known_us = wall_start;
  while (!rig.panel().quit() && !stop) {
    // Run: at most kLeadUs of simulated time per pass, never past the pacer.
    const uint64_t now_sim = rig.now_us();
    uint64_t target = pacer.allowed_sim_us(now_sim, wall_known_us);
    if (target > now_sim + uno::Pacer::kLeadUs) target = now_sim + uno::Pacer::kLeadUs;
    if (target > end_us) target = end_us;
    ++io.passes;
    if (target > now_sim && !rig.run_until_us(target)) {
      exit_code = fail("image stopped: " + rig.board().stop_reason());
      break;
    }
    // Out, all the pass produced at once: serial bytes, CAN frames, panel lines.
    const std::string out = rig.take_serial_out();
    if (!out.empty()) {
      ++io.writes;
      const Status written = serial.write(reinterpret_cast<const uint8_t*>(out.data()), out.size());
      if (!written) {
        exit_code = fail(written.message());
        break;
      }
    }
    const std::vector<uno::CanWire::Sent> sent = rig.take_can_out();
    if (with_can && !sent.empty()) {
      std::vector<CanFrame> frames;
      frames.reserve(sent.size());
      for (const uno::CanWire::Sent& s : sent) frames.push_back(s.frame);
      io.writes +=
          (frames.size() + linux_port::SocketCanPort::kBatch - 1) / linux_port::SocketCanPort::kBatch;
      can.send(frames.data(), frames.size());  // refusals are counted by the port, as on a bus off
    }
    if (opt.trace_can) {
      for (const uno::CanWire::Sent& s : sent) {
        const uint64_t sent_us = s.end_cycle / (uno::UnoBoard::kCpuHz / 1000000u);
        say("can " + candump_frame_text(s.frame) + " sim_us=" + std::to_string(sent_us) +
            " at_us=" + std::to_string(at_us(sent_us)));
      }
    }
    uint64_t led_us = 0;
    if (rig.take_led_change(&led_us)) show_leds(led_us);
    if (rig.panel().settle_blinks(rig.now_us())) show_leds(rig.now_us());
    if (!ready_said && rig.modbus_ready()) {
      ready_said = true;
      say("ready node=" + std::to_string(rig.booted_node()) + " can=" + opt.can + " serial=" + serial.path() +
          (serial.link_path().empty() ? "" : " link=" + serial.link_path()));
    }
    if (!opt.unpaced) {
      ++io.clock_reads;
      wall_known_us = wall_us();
      const std::string slow = pacer.slow_report(rig.now_us(), wall_known_us);
      if (!slow.empty()) fprintf(stderr, "mb2co-uno: %s\n", slow.c_str());
    }
    if (rig.now_us() >= end_us) break;

    // In: wait for the wall clock to catch up, in one poll that also sees
    // input. Input that wakes it early is taken at once, then the rest of
    // the wait is slept without watching (one more wake-up, not one per
    // frame or byte) and the inputs polled once more, so that all that came
    // before the end of the wait reaches the next run: at most kLeadUs late.
    const uint64_t wait = pacer.wait_us(rig.now_us(), wall_known_us);
    pollfd fds[4];
    bool cut = false;
    const int ready = poll_inputs(fds, wait, &cut);
    if (ready < 0 || (ready > 0 && !take_input(fds))) break;
    if (ready > 0 && wait > 0 && !stop) {
      const uint64_t due_us = wall_known_us + wait;
      const timespec due{static_cast<time_t>(due_us / 1000000u), static_cast<long>(due_us % 1000000u) * 1000};
      ++io.sleeps;
      cut = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, nullptr) != 0;
      const int more = poll_inputs(fds, 0, &cut);
      if (more < 0 || (more > 0 && !take_input(fds))) break;
    }
    // The wall clock has reached the end of the wait, unless a signal cut
    // it short (then the pacer finds no time to run and the next pass waits
    // again).
    if (!cut) wall_known_us += wait;

    for (size_t nl; (nl = input.find('\n')) != std::string::npos;) {
      const std::string line = input.substr(0, nl);
      // The stack's high-water mark and the wire's counts are the
      // board's, not the panel's.
      const std::string times = " at_us=" + std::to_string(at_us(rig.now_us())) +
                                " sim_us=" + std::to_string(static_cast<uint32_t>(rig.now_us()));
      const std::string reply =
          line == "stack?" ? "stack used=" + std::to_string(rig.board().stack_used()) +
                                 " room=" + std::to_string(rig.board().stack_room()) + times
          : line == "bus?"
              ? "bus in=" + std::to_string(rig.wire().carried_in()) +
                    " dropped=" + std::to_string(rig.wire().rx_dropped()) + " busy_us=" +
                    std::to_string(rig.wire().busy_cycles() / (uno::UnoBoard::kCpuHz / 1000000u)) + times
              : rig.panel().handle(line, rig.now_us(), at_us(rig.now_us()));
      input.erase(0, nl + 1);
      if (!reply.empty()) say(reply);
    }
    rig.panel().process(rig.now_us());
    rig.apply_buttons();
  }

  serial.close();
  can.close();
  if (!opt.eeprom.empty()) {
    rig.board().get_eeprom(eeprom.bytes(), eeprom.size());
    const Status saved = eeprom.save();
    if (!saved && exit_code == 0) exit_code = fail(saved.message());
  }
  const double sim_s = static_cast<double>(rig.now_us()) / 1e6;
  const double wall_s = static_cast<double>(wall_us() - wall_start) / 1e6;
  // What was lost to hold-ups (the host not running us for more than
  // kBehindUs: a loaded machine, user-mode Linux) is said apart from the rest.
  fprintf(stderr,
          "mb2co-uno: %.3f s simulated in %.3f s wall (%.2fx real time; %llu hold-ups over %llu ms: %.3f s "
          "dropped)\n",
          sim_s, wall_s, wall_s > 0 ? sim_s / wall_s : 0.0, static_cast<unsigned long long>(pacer.jumps()),
          static_cast<unsigned long long>(uno::Pacer::kBehindUs / 1000u),
          static_cast<double>(pacer.dropped_us()) / 1e6);
  if (opt.stats) {
    rusage used{};
    getrusage(RUSAGE_SELF, &used);
    const uint64_t cpu_us = static_cast<uint64_t>(used.ru_utime.tv_sec + used.ru_stime.tv_sec) * 1000000u +
                            static_cast<uint64_t>(used.ru_utime.tv_usec + used.ru_stime.tv_usec);
    fprintf(stderr, "mb2co-uno: %s\n", io.line(rig.now_us(), cpu_us).c_str());
  }
  return exit_code;
}
