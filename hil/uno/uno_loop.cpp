#include "uno_loop.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <vector>

#include "host/candump_text.h"

namespace mb2co {
namespace uno {

namespace {

uint64_t wall_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint64_t>(ts.tv_sec) * 1000000u + static_cast<uint64_t>(ts.tv_nsec) / 1000u;
}

// Control-channel output: whole lines, flushed at once (tests wait for them).
void say(const std::string& line) {
  fputs(line.c_str(), stdout);
  fputc('\n', stdout);
  fflush(stdout);
}

}  // namespace

Status UnoWiring::open(const UnoOptions& opt, UnoRig& rig) {
  Status loaded = rig.load(opt.elf);
  if (!loaded) return loaded;
  if (!opt.eeprom.empty()) {
    Status read = eeprom.load();
    if (!read) return read;
    rig.board().set_eeprom(eeprom.bytes(), eeprom.size());
  }
  if (with_can) {
    Status bound = can.open(opt.can.c_str());
    if (bound) bound = can.accept_all();
    if (!bound) return bound;
  }
  return serial.create_pty(opt.pty_link);
}

Status UnoWiring::close(const UnoOptions& opt, UnoRig& rig) {
  serial.close();
  can.close();
  if (opt.eeprom.empty()) return Status::ok();
  rig.board().get_eeprom(eeprom.bytes(), eeprom.size());
  return eeprom.save();
}

UnoLoop::UnoLoop(const UnoOptions& opt, UnoRig& rig, UnoWiring& wiring, int stop_fd)
    : opt_(opt),
      rig_(rig),
      wiring_(wiring),
      stop_fd_(stop_fd),
      wall_start_(wall_us()),
      pacer_(!opt.unpaced, wall_start_, 0),
      end_us_(opt.duration_ms ? uint64_t{opt.duration_ms} * 1000u : UINT64_MAX),
      wall_known_us_(wall_start_) {}

int UnoLoop::fail(const std::string& what) {
  fprintf(stderr, "mb2co-uno: %s\n", what.c_str());
  return 1;
}

// A "leds" line for each change of what the five LEDs show (the image
// rewrites pins with the level they have: no line for that).
void UnoLoop::show_leds(uint64_t sim_us) {
  const std::string line = rig_.panel().leds_line(at_us(sim_us));
  const std::string levels = line.substr(0, line.rfind(" at_us="));
  if (levels == leds_shown_) return;
  leds_shown_ = levels;
  say(line);
}

int UnoLoop::run() {
  show_leds(0);
  while (!rig_.panel().quit() && !stop_) {
    if (!run_pass()) break;
    if (rig_.now_us() >= end_us_) break;
    if (!wait_for_the_clock()) break;
    answer_commands();
    rig_.panel().process(rig_.now_us());
    rig_.apply_buttons();
  }
  return exit_code_;
}

bool UnoLoop::run_pass() {
  // Run: at most kLeadUs of simulated time per pass, never past the pacer.
  const uint64_t now_sim = rig_.now_us();
  uint64_t target = pacer_.allowed_sim_us(now_sim, wall_known_us_);
  if (target > now_sim + Pacer::kLeadUs) target = now_sim + Pacer::kLeadUs;
  if (target > end_us_) target = end_us_;
  ++io_.passes;
  if (target > now_sim && !rig_.run_until_us(target)) {
    exit_code_ = fail("image stopped: " + rig_.board().stop_reason());
    return false;
  }
  // Out, all the pass produced at once: serial bytes, CAN frames, panel lines.
  const std::string out = rig_.take_serial_out();
  if (!out.empty()) {
    ++io_.writes;
    const Status written = wiring_.serial.write(reinterpret_cast<const uint8_t*>(out.data()), out.size());
    if (!written) {
      exit_code_ = fail(written.message());
      return false;
    }
  }
  send_can(rig_.take_can_out());
  uint64_t led_us = 0;
  if (rig_.take_led_change(&led_us)) show_leds(led_us);
  if (rig_.panel().settle_blinks(rig_.now_us())) show_leds(rig_.now_us());
  if (!ready_said_ && rig_.modbus_ready()) {
    ready_said_ = true;
    const port::SerialPort& serial = wiring_.serial;
    say("ready node=" + std::to_string(rig_.booted_node()) + " can=" + opt_.can + " serial=" + serial.path() +
        (serial.link_path().empty() ? "" : " link=" + serial.link_path()));
  }
  if (!opt_.unpaced) {
    ++io_.clock_reads;
    wall_known_us_ = wall_us();
    const std::string slow = pacer_.slow_report(rig_.now_us(), wall_known_us_);
    if (!slow.empty()) fprintf(stderr, "mb2co-uno: %s\n", slow.c_str());
  }
  return true;
}

void UnoLoop::send_can(const std::vector<CanWire::Sent>& sent) {
  if (wiring_.with_can && !sent.empty()) {
    std::vector<CanFrame> frames;
    frames.reserve(sent.size());
    for (const CanWire::Sent& s : sent) frames.push_back(s.frame);
    io_.writes += (frames.size() + linux_port::SocketCanPort::kBatch - 1) / linux_port::SocketCanPort::kBatch;
    wiring_.can.send(frames.data(), frames.size());  // refusals are counted by the port, as on a bus off
  }
  if (opt_.trace_can) {
    for (const CanWire::Sent& s : sent) {
      const uint64_t sent_us = s.end_cycle / (UnoBoard::kCpuHz / 1000000u);
      say("can " + candump_frame_text(s.frame) + " sim_us=" + std::to_string(sent_us) +
          " at_us=" + std::to_string(at_us(sent_us)));
    }
  }
}

bool UnoLoop::wait_for_the_clock() {
  // In: wait for the wall clock to catch up, in one poll that also sees
  // input. Input that wakes it early is taken at once, then the rest of
  // the wait is slept without watching (one more wake-up, not one per
  // frame or byte) and the inputs polled once more, so that all that came
  // before the end of the wait reaches the next run: at most kLeadUs late.
  const uint64_t wait = pacer_.wait_us(rig_.now_us(), wall_known_us_);
  pollfd fds[4];
  bool cut = false;
  const int ready = poll_inputs(fds, wait, &cut);
  if (ready < 0 || (ready > 0 && !take_input(fds))) return false;
  if (ready > 0 && wait > 0 && !stop_) {
    const uint64_t due_us = wall_known_us_ + wait;
    const timespec due{static_cast<time_t>(due_us / 1000000u), static_cast<long>(due_us % 1000000u) * 1000};
    ++io_.sleeps;
    cut = clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &due, nullptr) != 0;
    const int more = poll_inputs(fds, 0, &cut);
    if (more < 0 || (more > 0 && !take_input(fds))) return false;
  }
  // The wall clock has reached the end of the wait, unless a signal cut
  // it short (then the pacer finds no time to run and the next pass waits
  // again).
  if (!cut) wall_known_us_ += wait;
  return true;
}

// Polls every input, waiting up to `wait_us`; the number ready (-1:
// failed, exit_code_ set; 0 also when a signal cut the wait short, then
// `*cut` is set).
int UnoLoop::poll_inputs(pollfd* fds, uint64_t wait_us, bool* cut) {
  fds[0] = {wiring_.serial.fd(), POLLIN, 0};
  fds[1] = {stop_fd_, POLLIN, 0};
  fds[2] = {stdin_open_ ? 0 : -1, POLLIN, 0};
  fds[3] = {wiring_.with_can ? wiring_.can.fd() : -1, POLLIN, 0};
  const timespec timeout{static_cast<time_t>(wait_us / 1000000u),
                         static_cast<long>(wait_us % 1000000u) * 1000};
  ++io_.polls;
  const int ready = ppoll(fds, 4, &timeout, nullptr);
  if (ready >= 0) return ready;
  if (errno == EINTR) {
    *cut = true;
    return 0;
  }
  exit_code_ = fail(std::string("poll: ") + strerror(errno));
  return -1;
}

// Every input with something waiting, one read each (CAN: again while a
// batch comes back full); false on a failure (exit_code_ set).
bool UnoLoop::take_input(const pollfd* fds) {
  if (fds[1].revents & POLLIN) stop_ = true;  // SIGINT / SIGTERM: clean exit
  if (fds[0].revents & (POLLIN | POLLERR | POLLHUP)) {
    uint8_t bytes[256];
    uint32_t stamps[256];
    size_t n = 0;
    ++io_.reads;
    const Status got = wiring_.serial.read(bytes, stamps, sizeof bytes, &n);
    if (!got) {
      exit_code_ = fail(got.message());
      return false;
    }
    rig_.serial_in(bytes, n);
  }
  if (fds[3].revents & POLLIN) take_can_frames();
  if (fds[2].revents & (POLLIN | POLLHUP)) {
    char buf[512];
    ++io_.reads;
    const ssize_t r = read(0, buf, sizeof buf);
    if (r <= 0) {
      stdin_open_ = false;  // no more commands; run on until a signal
    } else {
      input_.append(buf, static_cast<size_t>(r));
    }
  }
  return true;
}

void UnoLoop::take_can_frames() {
  linux_port::TimedCanFrame frames[linux_port::SocketCanPort::kBatch];
  size_t got = 0;
  do {
    ++io_.reads;
    got = wiring_.can.receive(frames, linux_port::SocketCanPort::kBatch);
    // A batch's kernel stamps are wall-clock time: the port reads both
    // clocks once to move them onto the monotonic one.
    if (got > 0) io_.clock_reads += 2;
    io_.can_frames_in += got;
    // At the kernel's receive time: a backlog read after the host held
    // us up keeps its spacing (a burst would overrun the chip's buffers).
    for (size_t i = 0; i < got; ++i) rig_.can_in(frames[i].frame, pacer_.sim_of(frames[i].rx_time_us));
  } while (got == linux_port::SocketCanPort::kBatch);
}

void UnoLoop::answer_commands() {
  for (size_t nl; (nl = input_.find('\n')) != std::string::npos;) {
    const std::string reply = answer(input_.substr(0, nl));
    input_.erase(0, nl + 1);
    if (!reply.empty()) say(reply);
  }
}

std::string UnoLoop::answer(const std::string& line) {
  // The stack's high-water mark and the wire's counts are the
  // board's, not the panel's.
  const std::string times = " at_us=" + std::to_string(at_us(rig_.now_us())) +
                            " sim_us=" + std::to_string(static_cast<uint32_t>(rig_.now_us()));
  if (line == "stack?")
    return "stack used=" + std::to_string(rig_.board().stack_used()) +
           " room=" + std::to_string(rig_.board().stack_room()) + times;
  if (line == "bus?")
    return "bus in=" + std::to_string(rig_.wire().carried_in()) +
           " dropped=" + std::to_string(rig_.wire().rx_dropped()) +
           " overflowed=" + std::to_string(rig_.wire().rx_overflowed()) +
           " busy_us=" + std::to_string(rig_.wire().busy_cycles() / (UnoBoard::kCpuHz / 1000000u)) + times;
  return rig_.panel().handle(line, rig_.now_us(), at_us(rig_.now_us()));
}

void UnoLoop::report() const {
  const double sim_s = static_cast<double>(rig_.now_us()) / 1e6;
  const double wall_s = static_cast<double>(wall_us() - wall_start_) / 1e6;
  // What was lost to hold-ups (the host not running us for more than
  // kBehindUs: a loaded machine, user-mode Linux) is said apart from the rest.
  fprintf(stderr,
          "mb2co-uno: %.3f s simulated in %.3f s wall (%.2fx real time; %llu hold-ups over %llu ms: %.3f s "
          "dropped)\n",
          sim_s, wall_s, wall_s > 0 ? sim_s / wall_s : 0.0, static_cast<unsigned long long>(pacer_.jumps()),
          static_cast<unsigned long long>(Pacer::kBehindUs / 1000u),
          static_cast<double>(pacer_.dropped_us()) / 1e6);
  if (opt_.stats) {
    rusage used{};
    getrusage(RUSAGE_SELF, &used);
    const uint64_t cpu_us = static_cast<uint64_t>(used.ru_utime.tv_sec + used.ru_stime.tv_sec) * 1000000u +
                            static_cast<uint64_t>(used.ru_utime.tv_usec + used.ru_stime.tv_usec);
    fprintf(stderr, "mb2co-uno: %s\n", io_.line(rig_.now_us(), cpu_us).c_str());
  }
}

}  // namespace uno
}  // namespace mb2co
