// mb2co-master run to its end with what a bound on it needs: the exit
// status, when it exited on the monotonic clock (a pidfd wakes the wait, no
// polling), and its peak resident memory (wait4's ru_maxrss, the kernel's
// VmHWM of the child). stdout and stderr go to files and are read back.
#pragma once
#include <chrono>
#include <string>
#include <vector>

#include "rogue_server.h"

namespace mb2co {
namespace test {

struct MeasuredRun {
  int exit_code = -1;  ///< 128 + N when killed by signal N; -1 when it did not end in time (then killed)
  std::string out;
  std::string err;
  long max_rss_kib = 0;
  Clock::time_point exited_at{};
  std::string error;  ///< why it could not be run at all
};

/// Runs `mb2co-master -i vcan0 ARGS...`, `dir` for its output files; kills
/// it after `timeout`.
MeasuredRun run_measured(const std::vector<std::string>& args, const std::string& dir,
                         std::chrono::milliseconds timeout);

}  // namespace test
}  // namespace mb2co
