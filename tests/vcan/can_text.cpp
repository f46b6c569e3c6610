#include "can_text.h"

#include <stdio.h>
#include <string.h>

#include "host/candump_text.h"

namespace mb2co {
namespace test {

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// Parses `count` hex digits; -1 when one is not hex.
long parse_hex(const std::string& text, size_t count) {
  long value = 0;
  for (size_t i = 0; i < count; ++i) {
    const int digit = hex_value(text[i]);
    if (digit < 0) return -1;
    value = value * 16 + digit;
  }
  return value;
}

}  // namespace

std::string to_text(const CanFrame& frame) {
  return candump_frame_text(frame);
}

bool from_text(const std::string& text, CanFrame& frame) {
  const size_t hash = text.find('#');
  if (hash != 3 && hash != 8) return false;
  const long id = parse_hex(text, hash);
  if (id < 0) return false;
  frame = CanFrame{};
  frame.id = static_cast<uint32_t>(id);
  frame.flags = hash == 8 ? CanFrame::kExtended : 0;
  const std::string payload = text.substr(hash + 1);
  if (!payload.empty() && payload[0] == 'R') {
    frame.flags = static_cast<uint8_t>(frame.flags | CanFrame::kRtr);
    if (payload.size() > 2) return false;
    const int dlc = payload.size() == 2 ? payload[1] - '0' : 0;
    if (dlc < 0 || dlc > 8) return false;
    frame.dlc = static_cast<uint8_t>(dlc);
    return true;
  }
  if (payload.size() % 2 != 0 || payload.size() > 16) return false;
  frame.dlc = static_cast<uint8_t>(payload.size() / 2);
  for (size_t i = 0; i < frame.dlc; ++i) {
    const long byte = parse_hex(payload.substr(2 * i), 2);
    if (byte < 0) return false;
    frame.data[i] = static_cast<uint8_t>(byte);
  }
  return true;
}

std::string candump_frame_field(const std::string& line) {
  const size_t space = line.rfind(' ');
  return space == std::string::npos ? std::string() : line.substr(space + 1);
}

bool same_frame(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.flags != b.flags || a.dlc != b.dlc) return false;
  return a.rtr() || a.dlc > 8 || memcmp(a.data, b.data, a.dlc) == 0;
}

CanFrame make_frame(uint32_t id, uint8_t flags, uint8_t dlc, const char* hex_data) {
  CanFrame frame{};
  frame.id = id;
  frame.flags = flags;
  frame.dlc = dlc;
  for (size_t i = 0; i < dlc && i < 8 && hex_data[2 * i] != '\0' && hex_data[2 * i + 1] != '\0'; ++i) {
    frame.data[i] = static_cast<uint8_t>(hex_value(hex_data[2 * i]) * 16 + hex_value(hex_data[2 * i + 1]));
  }
  return frame;
}

}  // namespace test
}  // namespace mb2co
