#include "wall_time.h"

#include <stdio.h>
#include <time.h>

namespace mb2co {
namespace master {

bool time_of_day_of_unix_ms(int64_t unix_ms, canopen::TimeOfDay* out) {
  if (unix_ms < kCanopenEpochUnixMs) return false;
  const int64_t since_ms = unix_ms - kCanopenEpochUnixMs;
  const int64_t days = since_ms / canopen::kMsPerDay;
  if (days > 0xFFFF) return false;
  out->days = static_cast<uint16_t>(days);
  out->ms = static_cast<uint32_t>(since_ms % canopen::kMsPerDay);
  return true;
}

std::string utc_text(const canopen::TimeOfDay& t) {
  const time_t seconds =
      static_cast<time_t>(kCanopenEpochUnixMs / 1000 + int64_t{t.days} * 86400 + t.ms / 1000);
  struct tm utc;
  gmtime_r(&seconds, &utc);
  char text[80];  // room for any int the format could print (-Wformat-truncation)
  snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03uZ", utc.tm_year + 1900, utc.tm_mon + 1,
           utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, static_cast<unsigned>(t.ms % 1000));
  return text;
}

int64_t wall_clock_unix_ms() {
  struct timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  return int64_t{now.tv_sec} * 1000 + now.tv_nsec / 1000000;
}

}  // namespace master
}  // namespace mb2co
