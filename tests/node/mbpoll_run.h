// mbpoll (Debian) run once to its end for the mb2co-node tests, on the pty
// (-m rtu) or on TCP (-m tcp): its exit status and the values it printed.
#pragma once
#include <regex>
#include <string>
#include <vector>

#include "line_child.h"

namespace mb2co {
namespace test {

struct MbpollRun {
  int status = -1;
  std::vector<std::string> values;  ///< "[ref]: value" lines, in order
  std::string output;               ///< stdout and stderr, for messages
};

/// Runs `argv` (mbpoll and its arguments) to its end.
inline MbpollRun run_mbpoll(const std::vector<std::string>& argv) {
  using namespace std::chrono_literals;
  MbpollRun run;
  LineChild child;
  if (!child.start(argv)) return run;
  static const std::regex kValue(R"(^\[(\d+)\]:\s+(\S+))");
  std::string line;
  while (child.wait_line([](const std::string&) { return true; }, 30s, &line)) {
    run.output += line + "\n";
    std::smatch m;
    if (std::regex_search(line, m, kValue)) run.values.push_back(m[2]);
  }
  run.status = child.wait_exit(30s);
  run.output += child.stderr_text();
  return run;
}

}  // namespace test
}  // namespace mb2co
