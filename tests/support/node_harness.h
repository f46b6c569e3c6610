// What the mb2co-node tests share: the node as a child process (ready line,
// control channel) and a libmodbus master on its serial line.
// Every wait polls for a condition with a deadline that only bounds a failure.
#pragma once
#include <modbus.h>
#include <stdint.h>

#include <chrono>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "host/status.h"
#include "line_child.h"
#include "rtu_frames.h"

namespace mb2co {
namespace test {

using namespace std::chrono_literals;

/// Path of the mb2co-node binary under test.
const char* node_program();

/// CLOCK_MONOTONIC in µs truncated to 32 bits: the clock of the node's at_us.
uint32_t monotonic_us();

/// The node's own time stamp (at_us=) of a leds/state line; 0 when absent.
uint32_t at_us_of(const std::string& line);

/// A fresh directory under $TMPDIR (or /tmp), removed with its files.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

 private:
  std::string dir_;
};

/// mb2co-node under test.
class NodeProcess {
 public:
  /// Starts it with `args` and waits for its ready line; false with the
  /// reason in error() when it does not get there within `timeout`.
  bool start(const std::vector<std::string>& args, std::chrono::milliseconds timeout = 10s);
  /// The same for another program with this control channel and ready line
  /// (`argv[0]` is its path: mb2co-uno, tests/uno).
  bool start_command(const std::vector<std::string>& argv, std::chrono::milliseconds timeout);
  /// The ready line's node id and device (the link when it made one).
  int node_id() const { return node_id_; }
  const std::string& device() const { return device_; }
  /// The ready line's Modbus/TCP address ("127.0.0.1:40123"; "" without --tcp).
  const std::string& tcp_address() const { return tcp_; }
  const std::string& error() const { return error_; }

  /// Sends a control command and returns the first line starting with
  /// `reply_prefix` ("" on timeout). Event lines before it are consumed.
  std::string ask(const std::string& command, const std::string& reply_prefix,
                  std::chrono::milliseconds timeout = 10s);
  /// Polls `counters?` until the counters line satisfies `match`.
  bool wait_counters(const std::function<bool(const std::string&)>& match,
                     std::chrono::milliseconds timeout = 10s);
  /// Waits for an event line starting with `prefix` and satisfying `match`.
  bool wait_event(const std::string& prefix, const std::function<bool(const std::string&)>& match,
                  std::chrono::milliseconds timeout, std::string* line = nullptr);
  /// The program's own clock now (µs, 32 bits): mb2co-node's at_us, which is
  /// its CLOCK_MONOTONIC (UnoProcess: the image's micros()).
  uint32_t device_us();
  /// SIGTERM (or `sig`) and the exit status (see LineChild::wait_exit).
  int stop(int sig = 15, std::chrono::milliseconds timeout = 10s);

  LineChild child;

 private:
  int node_id_ = 0;
  std::string device_;
  std::string tcp_;
  std::string error_;
};

/// Starts `candump -L vcan0` in `candump` and makes sure it listens: it must
/// see a probe (an extended id no CANopen node uses) before any node starts;
/// a probe sent before candump has bound its socket is lost, so probes are
/// sent until one is seen. Fails with the reason.
Status start_candump_listening(LineChild& candump, std::chrono::milliseconds timeout);

/// A libmodbus RTU master (115200 8N1, slave 1) on `device`.
class ModbusMaster {
 public:
  ModbusMaster() = default;
  ~ModbusMaster() { close(); }
  ModbusMaster(const ModbusMaster&) = delete;
  ModbusMaster& operator=(const ModbusMaster&) = delete;

  /// False with error() when libmodbus cannot open it.
  bool open(const std::string& device, std::chrono::milliseconds response_timeout = 500ms);
  void close();
  modbus_t* ctx() const { return ctx_; }
  int fd() const { return modbus_get_socket(ctx_); }
  const std::string& error() const { return error_; }

  /// One register/bit, -1 when the request fails.
  int input_register(int address);
  int holding_register(int address);
  /// Polls input register `address` until it equals `value`; false on timeout.
  bool wait_input(int address, int value, std::chrono::milliseconds timeout);
  /// Polls until every (input register, value) pair holds at once; false on
  /// timeout. Each round also reads input register 0 of every master in
  /// `also`: a station no PC asks for 2000h/9 (2 s) latches a stop (its Modbus
  /// watchdog), so a test that plays the PCs of a line keeps them all asking.
  bool wait_inputs(const std::vector<std::pair<int, int>>& want, std::chrono::milliseconds timeout,
                   const std::vector<ModbusMaster*>& also = {});
  /// Polls HR 11-12 (1010h/1) until they read 0 1: the save answered at once
  /// has been written (docs/register-map.md); false on timeout. What a save
  /// keeps is each entry as the save reached it: a test that changes an
  /// entry after "save" waits for this first.
  bool wait_saved(std::chrono::milliseconds timeout);
  /// A request PDU to slave 1 sent by libmodbus (for FCs its API lacks: 08,
  /// 2B); the response read from the port, without CRC (empty: none).
  Bytes raw_transaction(const Bytes& pdu);
  /// FC 08 counter `sub` (0Bh..12h); 0xFFFF when there is no proper answer.
  uint16_t diag_counter(uint8_t sub);

 private:
  modbus_t* ctx_ = nullptr;
  std::string error_;
};

}  // namespace test
}  // namespace mb2co
