// Test peer: our Modbus/RTU slave on a pseudo-terminal (or a real tty), with
// the in-memory bank laid out as in support/test_layout.h.
//
//   mb2co_modbus_pty_slave [--link PATH] [--tty PATH [--parity none|even|odd]
//                          [--stop-bits 1|2]] [--baud N] [--address N]
//                          [--events] [--no-t15]
//
// Prints "ready <device path>" once it serves, then runs until SIGTERM,
// SIGINT or end of stdin. With --events it also prints
//   "counters bus=N comm=N exc=N srv=N noresp=N ovr=N t15=N"
// after every change, once the response (if any) has been written, so a test
// can wait for the slave to have handled a frame instead of sleeping.
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <string>

#include "modbus/slave.h"
#include "platform/serial_port.h"
#include "support/memory_bank.h"
#include "support/test_layout.h"

namespace {

using namespace mb2co;
using namespace mb2co::modbus;

volatile sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

struct Options {
  std::string link, tty;
  modbus::Parity parity = modbus::Parity::kNone;
  unsigned stop_bits = 1;
  uint32_t baud = 115200;
  uint8_t address = test::kSlaveAddress;
  bool events = false;
  bool check_t15 = true;
};

[[noreturn]] void usage_error(const std::string& message) {
  fprintf(stderr, "mb2co_modbus_pty_slave: %s\n", message.c_str());
  exit(2);
}

uint32_t parse_number(const char* text, uint32_t min, uint32_t max, const char* what) {
  char* end = nullptr;
  errno = 0;
  const unsigned long v = strtoul(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || v < min || v > max) {
    usage_error(std::string("bad ") + what + " '" + text + "'");
  }
  return static_cast<uint32_t>(v);
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage_error("missing value after " + a);
      return argv[++i];
    };
    if (a == "--link") {
      o.link = value();
    } else if (a == "--tty") {
      o.tty = value();
    } else if (a == "--parity") {
      const std::string p = value();
      if (p == "none")
        o.parity = modbus::Parity::kNone;
      else if (p == "even")
        o.parity = modbus::Parity::kEven;
      else if (p == "odd")
        o.parity = modbus::Parity::kOdd;
      else
        usage_error("bad parity '" + p + "'");
    } else if (a == "--stop-bits") {
      o.stop_bits = parse_number(value(), 1, 2, "stop bits");
    } else if (a == "--baud") {
      o.baud = parse_number(value(), 300, 4000000, "baud rate");
    } else if (a == "--address") {
      o.address = static_cast<uint8_t>(parse_number(value(), 1, 247, "address"));
    } else if (a == "--events") {
      o.events = true;
    } else if (a == "--no-t15") {
      o.check_t15 = false;
    } else {
      usage_error("unknown option '" + a + "'");
    }
  }
  return o;
}

bool write_to_port(void* ctx, const uint8_t* data, uint16_t length) {
  return static_cast<port::SerialPort*>(ctx)->write(data, length).is_ok();
}

bool same(const DiagCounters& a, const DiagCounters& b, uint16_t t15a, uint16_t t15b) {
  return a.bus_messages == b.bus_messages && a.bus_comm_errors == b.bus_comm_errors &&
         a.exceptions == b.exceptions && a.server_messages == b.server_messages &&
         a.no_responses == b.no_responses && a.char_overruns == b.char_overruns && t15a == t15b;
}

// ppoll timeout until the slave's next deadline (null: none).
const timespec* timeout_until(const Slave& slave, timespec& ts) {
  uint32_t at_us = 0;
  if (!slave.deadline(at_us)) return nullptr;
  const int32_t left = static_cast<int32_t>(at_us - port::monotonic_us());
  const uint32_t wait_us = left > 0 ? static_cast<uint32_t>(left) : 0u;
  ts.tv_sec = wait_us / 1000000u;
  ts.tv_nsec = static_cast<long>(wait_us % 1000000u) * 1000L;
  return &ts;
}

}  // namespace

int main(int argc, char** argv) {
  const Options opt = parse_options(argc, argv);

  port::SerialPort serial;
  const Status opened = opt.tty.empty() ? serial.create_pty(opt.link)
                                        : serial.open_tty(opt.tty, opt.baud, opt.parity, opt.stop_bits);
  if (!opened) {
    fprintf(stderr, "mb2co_modbus_pty_slave: %s\n", opened.message().c_str());
    return 1;
  }

  test::MemoryBank bank(test::kCoilCount, test::kDiscreteInputCount, test::kInputRegisterCount,
                        test::kHoldingRegisterCount);
  test::apply_test_layout(bank);
  test::FixedIdentity identity = test::test_identity();
  Slave slave(bank, &identity, ByteSink{&write_to_port, &serial}, opt.address, rtu_timing(opt.baud));
  slave.set_check_t15(opt.check_t15);

  // SIGTERM/SIGINT only while waiting in ppoll: no lost wake-up.
  struct sigaction sa = {};
  sa.sa_handler = on_signal;
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
  signal(SIGPIPE, SIG_IGN);
  sigset_t blocked, during_poll;
  sigemptyset(&blocked);
  sigaddset(&blocked, SIGTERM);
  sigaddset(&blocked, SIGINT);
  sigprocmask(SIG_BLOCK, &blocked, &during_poll);
  sigdelset(&during_poll, SIGTERM);
  sigdelset(&during_poll, SIGINT);

  printf("ready %s\n", serial.path().c_str());
  fflush(stdout);

  DiagCounters shown = slave.counters();
  uint16_t shown_t15 = slave.stats().t15_violations;
  pollfd fds[2] = {{serial.fd(), POLLIN, 0}, {STDIN_FILENO, POLLIN, 0}};
  uint8_t bytes[512];
  uint32_t stamps[512];
  while (!g_stop) {
    timespec ts;
    const int ready = ppoll(fds, 2, timeout_until(slave, ts), &during_poll);
    if (ready < 0 && errno != EINTR) {
      perror("mb2co_modbus_pty_slave: ppoll");
      return 1;
    }
    if (ready > 0 && (fds[1].revents & (POLLIN | POLLHUP)) != 0) {
      char sink[64];
      if (read(STDIN_FILENO, sink, sizeof sink) <= 0) break;  // end of stdin
    }
    // Drain the port; `now` is taken before the read that found it empty, so
    // every byte that arrived before `now` has been fed when process() runs.
    uint32_t now = 0;
    for (;;) {
      const uint32_t before = port::monotonic_us();
      size_t n = 0;
      const Status got = serial.read(bytes, stamps, sizeof bytes, &n);
      if (!got) {
        fprintf(stderr, "mb2co_modbus_pty_slave: %s\n", got.message().c_str());
        return 1;
      }
      if (n == 0) {
        now = before;
        break;
      }
      for (size_t i = 0; i < n; ++i) slave.on_byte(bytes[i], stamps[i]);
    }
    slave.process(now);
    if (opt.events && !same(shown, slave.counters(), shown_t15, slave.stats().t15_violations)) {
      shown = slave.counters();
      shown_t15 = slave.stats().t15_violations;
      printf("counters bus=%u comm=%u exc=%u srv=%u noresp=%u ovr=%u t15=%u\n", shown.bus_messages,
             shown.bus_comm_errors, shown.exceptions, shown.server_messages, shown.no_responses,
             shown.char_overruns, shown_t15);
      fflush(stdout);
    }
  }
  return 0;
}
