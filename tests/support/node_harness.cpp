#include "node_harness.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <filesystem>

namespace mb2co {
namespace test {

const char* node_program() {
  return MB2CO_NODE;
}

uint32_t monotonic_us() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000u +
                               static_cast<uint64_t>(ts.tv_nsec) / 1000u);
}

uint32_t at_us_of(const std::string& line) {
  return static_cast<uint32_t>(strtoul(field_of(line, "at_us").c_str(), nullptr, 10));
}

TempDir::TempDir() {
  const char* base = getenv("TMPDIR");
  std::string tmpl =
      std::string(base != nullptr && *base != '\0' ? base : "/tmp") + "/mb2co-node-test.XXXXXX";
  if (mkdtemp(tmpl.data()) != nullptr) dir_ = tmpl;
}

TempDir::~TempDir() {
  std::error_code ignored;
  if (!dir_.empty()) std::filesystem::remove_all(dir_, ignored);
}

bool NodeProcess::start(const std::vector<std::string>& args, std::chrono::milliseconds timeout) {
  std::vector<std::string> argv{node_program()};
  argv.insert(argv.end(), args.begin(), args.end());
  return start_command(argv, timeout);
}

bool NodeProcess::start_command(const std::vector<std::string>& argv, std::chrono::milliseconds timeout) {
  if (!child.start(argv)) {
    error_ = child.error();
    return false;
  }
  std::string ready;
  if (!child.wait_prefix("ready ", timeout, &ready)) {
    error_ = "no ready line; stderr: " + child.stderr_text();
    return false;
  }
  node_id_ = atoi(field_of(ready, "node").c_str());
  device_ = field_of(ready, "link");
  if (device_.empty()) device_ = field_of(ready, "serial");
  tcp_ = field_of(ready, "tcp");
  return true;
}

std::string NodeProcess::ask(const std::string& command, const std::string& reply_prefix,
                             std::chrono::milliseconds timeout) {
  std::string line;
  if (!child.send_line(command) || !child.wait_prefix(reply_prefix, timeout, &line)) return std::string();
  return line;
}

bool NodeProcess::wait_counters(const std::function<bool(const std::string&)>& match,
                                std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string line = ask("counters?", "counters ");
    if (line.empty()) return false;
    if (match(line)) return true;
  }
  return false;
}

bool NodeProcess::wait_event(const std::string& prefix, const std::function<bool(const std::string&)>& match,
                             std::chrono::milliseconds timeout, std::string* line) {
  return child.wait_line(
      [&](const std::string& l) { return l.compare(0, prefix.size(), prefix) == 0 && match(l); }, timeout,
      line);
}

uint32_t NodeProcess::device_us() {
  return at_us_of(ask("leds?", "leds "));
}

int NodeProcess::stop(int sig, std::chrono::milliseconds timeout) {
  child.signal(sig);
  return child.wait_exit(timeout);
}

bool ModbusMaster::open(const std::string& device, std::chrono::milliseconds response_timeout) {
  close();
  ctx_ = modbus_new_rtu(device.c_str(), 115200, 'N', 8, 1);
  if (ctx_ == nullptr || modbus_set_slave(ctx_, 1) != 0 || modbus_connect(ctx_) != 0) {
    error_ = "libmodbus on " + device + ": " + modbus_strerror(errno);
    close();
    return false;
  }
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(response_timeout).count();
  modbus_set_response_timeout(ctx_, static_cast<uint32_t>(us / 1000000), static_cast<uint32_t>(us % 1000000));
  return true;
}

void ModbusMaster::close() {
  if (ctx_ == nullptr) return;
  modbus_close(ctx_);
  modbus_free(ctx_);
  ctx_ = nullptr;
}

int ModbusMaster::input_register(int address) {
  uint16_t v = 0;
  return modbus_read_input_registers(ctx_, address, 1, &v) == 1 ? v : -1;
}

int ModbusMaster::holding_register(int address) {
  uint16_t v = 0;
  return modbus_read_registers(ctx_, address, 1, &v) == 1 ? v : -1;
}

bool ModbusMaster::wait_saved(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  do {
    uint16_t v[2] = {0xFFFF, 0xFFFF};
    if (modbus_read_registers(ctx_, 11, 2, v) == 2 && v[0] == 0 && v[1] == 1) return true;
  } while (std::chrono::steady_clock::now() < deadline);
  return false;
}

bool ModbusMaster::wait_input(int address, int value, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  do {
    if (input_register(address) == value) return true;
  } while (std::chrono::steady_clock::now() < deadline);
  return false;
}

bool ModbusMaster::wait_inputs(const std::vector<std::pair<int, int>>& want,
                               std::chrono::milliseconds timeout, const std::vector<ModbusMaster*>& also) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  do {
    for (ModbusMaster* other : also) {
      if (other != this) other->input_register(0);
    }
    bool all = true;
    for (const auto& w : want) all = all && input_register(w.first) == w.second;
    if (all) return true;
  } while (std::chrono::steady_clock::now() < deadline);
  return false;
}

Bytes ModbusMaster::raw_transaction(const Bytes& pdu) {
  Bytes req{1};
  req.insert(req.end(), pdu.begin(), pdu.end());
  if (modbus_send_raw_request(ctx_, req.data(), static_cast<int>(req.size())) <= 0) return {};
  return read_response(fd(), pdu.size(), 1s);
}

uint16_t ModbusMaster::diag_counter(uint8_t sub) {
  const Bytes rsp = raw_transaction({0x08, 0x00, sub, 0x00, 0x00});
  return rsp.size() == 6u ? static_cast<uint16_t>(rsp[4] << 8 | rsp[5]) : 0xFFFF;
}

Status start_candump_listening(LineChild& candump, std::chrono::milliseconds timeout) {
  if (!candump.start({"candump", "-L", "vcan0"})) return Status::failure(candump.error());
  for (const auto deadline = std::chrono::steady_clock::now() + timeout;
       std::chrono::steady_clock::now() < deadline;) {
    LineChild probe;
    if (!probe.start({"cansend", "vcan0", "1FFFFFFF#"}) || probe.wait_exit(timeout) != 0)
      return Status::failure("cansend failed");
    if (candump.wait_line([](const std::string& l) { return l.find(" 1FFFFFFF#") != std::string::npos; },
                          500ms))
      return Status::ok();
  }
  return Status::failure("candump never saw the probe");
}

}  // namespace test
}  // namespace mb2co
