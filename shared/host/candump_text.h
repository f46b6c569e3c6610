// CAN frames in can-utils' text notation: the frame field of cansend and
// `candump -L` ("123#11223344", "01234567#" with 8 hex digits = extended,
// "7FF#R", "123#R8" for an RTR with dlc 8), and whole `candump -L` log lines
// "(1.000000) can0 123#11", which canplayer replays and Wireshark opens.
#pragma once
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <string>

#include "canopen/can_frame.h"

namespace mb2co {

inline std::string candump_frame_text(const CanFrame& frame) {
  char out[40];
  int n = snprintf(out, sizeof out, frame.extended() ? "%08X#" : "%03X#", static_cast<unsigned>(frame.id));
  if (frame.rtr()) {
    snprintf(out + n, sizeof out - static_cast<size_t>(n), frame.dlc ? "R%u" : "R",
             static_cast<unsigned>(frame.dlc));
    return out;
  }
  for (unsigned i = 0; i < frame.dlc && i < 8; ++i)
    n += snprintf(out + n, sizeof out - static_cast<size_t>(n), "%02X", static_cast<unsigned>(frame.data[i]));
  return out;
}

/// One `candump -L` line (with '\n') for a frame seen at t_us on `iface`.
inline std::string candump_log_line(uint64_t t_us, const std::string& iface, const CanFrame& frame) {
  char stamp[40];
  snprintf(stamp, sizeof stamp, "(%010llu.%06llu) ", static_cast<unsigned long long>(t_us / 1000000),
           static_cast<unsigned long long>(t_us % 1000000));
  return stamp + iface + " " + candump_frame_text(frame) + "\n";
}

/// Reads one `candump -L` line back (the form candump_log_line writes:
/// "(SEC.USEC) IFACE ID#DATA", "ID#R", "ID#Rn"; 3 hex digits standard, 8
/// extended). False for anything else (a blank line, CAN FD "##").
inline bool parse_candump_log_line(const std::string& line, uint64_t* t_us, std::string* iface,
                                   CanFrame* frame) {
  const size_t dot = line.find('.');
  const size_t close = line.find(") ");
  if (line.empty() || line[0] != '(' || dot == std::string::npos || close == std::string::npos ||
      dot > close || close - dot != 7)
    return false;
  const size_t space = line.find(' ', close + 2);
  const std::string text = line.substr(space == std::string::npos ? line.size() : space + 1);
  const size_t hash = text.find('#');
  if (space == std::string::npos || hash == std::string::npos || (hash != 3 && hash != 8)) return false;
  char* end = nullptr;
  const unsigned long long sec = strtoull(line.c_str() + 1, &end, 10);
  if (end != line.c_str() + dot) return false;
  const unsigned long long usec = strtoull(line.c_str() + dot + 1, &end, 10);
  if (end != line.c_str() + close) return false;
  CanFrame f = {};
  f.id = static_cast<uint32_t>(strtoul(text.substr(0, hash).c_str(), &end, 16));
  if (*end != '\0' || f.id > (hash == 8 ? 0x1FFFFFFFu : 0x7FFu)) return false;
  if (hash == 8) f.flags |= CanFrame::kExtended;
  std::string data = text.substr(hash + 1);
  if (!data.empty() && data[0] == 'R') {
    f.flags |= CanFrame::kRtr;
    f.dlc = data.size() == 1 ? 0 : static_cast<uint8_t>(data[1] - '0');
    if (data.size() > 2 || f.dlc > 8) return false;
  } else {
    if (data.size() % 2 != 0 || data.size() > 16) return false;
    for (size_t i = 0; i < data.size(); i += 2) {
      f.data[f.dlc++] = static_cast<uint8_t>(strtoul(data.substr(i, 2).c_str(), &end, 16));
      if (*end != '\0') return false;
    }
  }
  *t_us = static_cast<uint64_t>(sec) * 1000000u + static_cast<uint64_t>(usec);
  *iface = line.substr(close + 2, space - close - 2);
  *frame = f;
  return true;
}

}  // namespace mb2co
