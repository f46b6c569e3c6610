#include "npm_peer.h"

#include <stdio.h>
#include <stdlib.h>

#include <fstream>
#include <sstream>

namespace mb2co {
namespace test {

std::vector<std::string> peer_command(const std::vector<std::string>& args) {
  std::vector<std::string> argv{MB2CO_NODEJS, MB2CO_CANOPEN_PEER, "--can", "vcan0"};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

std::string PeerResult::field(const std::string& name) const {
  return field_of(line, name);
}

uint32_t PeerResult::abort_code() const {
  const std::string code = field("code");
  return code.empty() ? 0u : static_cast<uint32_t>(strtoul(code.c_str(), nullptr, 16));
}

std::vector<uint8_t> PeerResult::data() const {
  const std::string hex = field("data");
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2)
    bytes.push_back(static_cast<uint8_t>(strtoul(hex.substr(i, 2).c_str(), nullptr, 16)));
  return bytes;
}

std::string PeerResult::describe() const {
  return "exit " + std::to_string(exit_code) + ", line '" + line + "', stderr '" + stderr_text + "'";
}

PeerResult run_peer_client(const std::vector<std::string>& args) {
  std::vector<std::string> full{"client"};
  full.insert(full.end(), args.begin(), args.end());
  PeerResult r;
  LineChild child;
  if (!child.start(peer_command(full))) {
    r.stderr_text = child.error();
    return r;
  }
  child.wait_line(
      [](const std::string& l) { return l.compare(0, 3, "ok ") == 0 || l.compare(0, 6, "abort ") == 0; },
      kPeerDeadline, &r.line);
  r.exit_code = child.wait_exit(kPeerDeadline);
  r.stderr_text = child.stderr_text();
  return r;
}

std::vector<uint8_t> peer_pattern(size_t size) {
  std::vector<uint8_t> b(size);
  for (size_t i = 0; i < size; ++i) b[i] = static_cast<uint8_t>(7 * i + (i >> 8));
  return b;
}

std::vector<uint8_t> other_content(size_t size, uint32_t seed) {
  std::vector<uint8_t> b(size);
  uint32_t x = seed;
  for (size_t i = 0; i < size; ++i) {
    x = x * 1664525u + 1013904223u;
    b[i] = static_cast<uint8_t>(x >> 24);
  }
  return b;
}

std::string to_hex(const std::vector<uint8_t>& bytes) {
  static const char kDigits[] = "0123456789abcdef";
  std::string s;
  for (uint8_t b : bytes) {
    s += kDigits[b >> 4];
    s += kDigits[b & 15];
  }
  return s;
}

bool write_file(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(f);
}

std::vector<uint8_t> read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

std::string eds_default(const std::string& eds_path, uint16_t index, uint8_t sub) {
  char section[24];
  if (sub == 0)
    snprintf(section, sizeof section, "[%04X]", index);
  else
    snprintf(section, sizeof section, "[%04Xsub%X]", index, sub);
  std::ifstream f(eds_path);
  std::string line;
  bool inside = false;
  while (std::getline(f, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '[') {
      inside = line == section;
    } else if (inside && line.compare(0, 13, "DefaultValue=") == 0) {
      return line.substr(13);
    }
  }
  return std::string();
}

}  // namespace test
}  // namespace mb2co
