#include "sim/event_log.h"

#include <charconv>
#include <cstdarg>
#include <cstdio>

namespace mb2co {
namespace sim {

void EventLog::add(SimNs t, int station, const char* event, const std::string& detail) {
  if (!enabled_) return;
  char head[24];
  char* end = std::to_chars(head, head + sizeof head, t).ptr;
  *end++ = ',';
  text_.append(head, end);
  text_ += run_;
  text_ += ',';
  if (station >= 0) text_ += std::to_string(station + 1);
  text_ += ',';
  text_ += event;
  text_ += ',';
  text_ += detail;
  text_ += '\n';
  ++lines_;
}

void append_hex_bytes(std::string* out, const uint8_t* d, size_t n) {
  static const char kDigits[] = "0123456789ABCDEF";
  for (size_t i = 0; i < n; ++i) {
    if (i != 0) *out += ' ';
    *out += kDigits[d[i] >> 4];
    *out += kDigits[d[i] & 15];
  }
}

std::string strf(const char* format, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, format);
  const int n = std::vsnprintf(buf, sizeof buf, format, ap);
  va_end(ap);
  return std::string(
      buf, n < 0 ? 0 : (n >= static_cast<int>(sizeof buf) ? sizeof buf - 1 : static_cast<size_t>(n)));
}

}  // namespace sim
}  // namespace mb2co
