#include "slave_process.h"

namespace mb2co {
namespace modbus {
namespace test {

bool SlaveProcess::start(const std::string& program, const std::vector<std::string>& args,
                         std::chrono::milliseconds timeout) {
  std::vector<std::string> argv{program};
  argv.insert(argv.end(), args.begin(), args.end());
  if (!child_.start(argv)) {
    error_ = "spawn " + program + ": " + child_.error();
    return false;
  }
  started_ = true;
  std::string line;
  if (!child_.wait_prefix("ready ", timeout, &line)) {
    error_ = program + " printed no ready line";
    return false;
  }
  device_ = line.substr(6);
  return true;
}

int SlaveProcess::stop() {
  if (!started_) return -1;
  child_.close_stdin();
  const int status = child_.wait_exit(std::chrono::seconds(30));
  return status >= 128 ? -1 : status;  // killed by a signal
}

}  // namespace test
}  // namespace modbus
}  // namespace mb2co
