#include "master_cli.h"

#include <cstdio>

namespace mb2co {
namespace test {

const char* master_program() {
  return MB2CO_MASTER;
}

std::string MasterRun::text() const {
  std::string s;
  for (const std::string& l : out) s += l + "\n";
  return s;
}

bool start_master(LineChild* child, const std::vector<std::string>& args) {
  std::vector<std::string> argv = {master_program(), "-i", "vcan0"};
  argv.insert(argv.end(), args.begin(), args.end());
  return child->start(argv);
}

MasterRun run_master(const std::vector<std::string>& args, std::chrono::milliseconds timeout) {
  MasterRun run;
  LineChild child;
  if (!start_master(&child, args)) {
    run.err = child.error();
    return run;
  }
  child.close_stdin();
  std::string line;
  while (child.wait_line([](const std::string&) { return true; }, timeout, &line)) run.out.push_back(line);
  run.exit_code = child.wait_exit(timeout);
  run.err = child.stderr_text();
  return run;
}

bool start_candump(LineChild* candump) {
  // A large receive buffer (8 MiB; we are root in the sandbox): a block or
  // segmented transfer floods the bus, and a frame candump dropped would
  // read as a frame never sent. -d reports drops ("DROPCOUNT: ...").
  if (!candump->start({"candump", "-d", "-r", "8388608", "-L", "vcan0"})) return false;
  // A probe sent before candump has bound its socket is lost: send until
  // one is seen.
  for (const auto deadline = std::chrono::steady_clock::now() + kVcanDeadline;
       std::chrono::steady_clock::now() < deadline;) {
    LineChild probe;
    if (!probe.start({"cansend", "vcan0", "1FFFFFFF#"}) || probe.wait_exit(kVcanDeadline) != 0) return false;
    if (candump->wait_line([](const std::string& l) { return l.find(" 1FFFFFFF#") != std::string::npos; },
                           500ms))
      return true;
  }
  return false;
}

bool parse_candump(const std::string& line, unsigned* id, std::vector<unsigned>* data) {
  char hex_id[16] = {};
  char hex_data[40] = {};
  const int n = std::sscanf(line.c_str(), "(%*[0-9.]) %*s %15[0-9A-Fa-f]#%39[0-9A-Fa-fR]", hex_id, hex_data);
  if (n < 1) return false;
  *id = static_cast<unsigned>(std::stoul(hex_id, nullptr, 16));
  data->clear();
  const std::string d = n == 2 ? hex_data : "";
  for (size_t i = 0; i + 1 < d.size(); i += 2)
    data->push_back(static_cast<unsigned>(std::stoul(d.substr(i, 2), nullptr, 16)));
  return true;
}

}  // namespace test
}  // namespace mb2co
