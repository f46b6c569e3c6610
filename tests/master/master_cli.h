// What the mb2co-master tests share: the program as a child (a run to its
// exit, or a long-running watch read line by line) and candump known to
// listen. Waits poll for output with deadlines that only bound a failure.
#pragma once
#include <chrono>
#include <string>
#include <vector>

#include "line_child.h"

namespace mb2co {
namespace test {

using namespace std::chrono_literals;

/// Bounds a failure only: user-mode Linux on a busy 2-core host is slow.
constexpr auto kVcanDeadline = 60s;

/// Path of mb2co-master under test.
const char* master_program();

/// One finished run of mb2co-master.
struct MasterRun {
  int exit_code = -1;
  std::vector<std::string> out;  ///< stdout lines
  std::string err;               ///< stderr
  std::string text() const;      ///< stdout joined with '\n'
};
/// Runs `mb2co-master -i vcan0 ARGS...` to its end.
MasterRun run_master(const std::vector<std::string>& args, std::chrono::milliseconds timeout = kVcanDeadline);
/// Starts it without waiting (watch, a transfer to be interrupted).
bool start_master(LineChild* child, const std::vector<std::string>& args);

/// candump -L vcan0, returned once it provably listens (it saw a probe
/// frame with an extended id no CANopen node uses).
bool start_candump(LineChild* candump);
/// A candump -L line as id and data bytes; false for other lines.
bool parse_candump(const std::string& line, unsigned* id, std::vector<unsigned>* data);

/// A DCF's text without 1013h's ParameterValue: the node's clock (TIME)
/// reads the instant of each read, so two dumps of one node differ there by
/// the time between them and nowhere else.
inline std::string without_clock(std::string dcf) {
  const size_t section = dcf.find("\n[1013]\n");
  if (section == std::string::npos) return dcf;
  const size_t value = dcf.find("\nParameterValue=", section);
  if (value != std::string::npos && value < dcf.find("\n[", section + 1))
    dcf.erase(value, dcf.find('\n', value + 1) - value);
  return dcf;
}

}  // namespace test
}  // namespace mb2co
