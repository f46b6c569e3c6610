#include "serve_harness.h"

#include <signal.h>

namespace mb2co {
namespace test {

bool ServeProcess::start(const std::string& listen, const std::vector<std::string>& serve_args,
                         const std::vector<std::string>& global_args) {
  std::vector<std::string> args = global_args;
  args.insert(args.end(), {"serve", "--listen", listen});
  args.insert(args.end(), serve_args.begin(), serve_args.end());
  if (!start_master(&child, args)) {
    error_ = child.error();
    return false;
  }
  std::string line;
  const std::string ready = "mb2co-master serve: listening on ";
  if (!child.wait_prefix(ready, kVcanDeadline, &line)) {
    error_ = "no listening line; stderr: " + child.stderr_text();
    return false;
  }
  where_ = line.substr(ready.size(), line.find(' ', ready.size()) - ready.size());
  return true;
}

bool ServeProcess::says(const std::string& text, std::string* line) {
  return child.wait_line([&](const std::string& l) { return l.find(text) != std::string::npos; },
                         kVcanDeadline, line);
}

int ServeProcess::stop() {
  child.signal(SIGTERM);
  return child.wait_exit(kVcanDeadline);
}

bool ServeClient::open(const std::string& where) {
  return child.start({"/usr/bin/python3", MB2CO_SERVE_CLIENT, where}) &&
         child.wait_prefix("connected", kVcanDeadline);
}

std::string ServeClient::ask(const std::string& line) {
  if (!child.send_line(line)) return std::string();
  return next();
}

std::string ServeClient::next() {
  std::string l;
  return child.wait_line([](const std::string&) { return true; }, kVcanDeadline, &l) ? l : std::string();
}

std::vector<uint8_t> base64_bytes(const std::string& text) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<uint8_t> out;
  uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    if (c == '=') break;
    const size_t v = alphabet.find(c);
    if (v == std::string::npos) return {};
    bits = bits << 6 | static_cast<uint32_t>(v);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out.push_back(static_cast<uint8_t>(bits >> count));
    }
  }
  return out;
}

}  // namespace test
}  // namespace mb2co
