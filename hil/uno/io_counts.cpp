#include "io_counts.h"

#include <stdio.h>

namespace mb2co {
namespace uno {

std::string IoCounts::line(uint64_t sim_us, uint64_t cpu_us) const {
  const double cpu_per_sim_s_ms =
      sim_us > 0 ? static_cast<double>(cpu_us) * 1e3 / static_cast<double>(sim_us) : 0.0;
  const double per_sim_s =
      sim_us > 0 ? static_cast<double>(system_calls()) * 1e6 / static_cast<double>(sim_us) : 0.0;
  char text[300];
  snprintf(text, sizeof text,
           "stats passes=%llu system_calls=%llu per_sim_s=%.0f clock=%llu poll=%llu sleep=%llu read=%llu "
           "write=%llu can_frames_in=%llu cpu_ms=%llu cpu_per_sim_s_ms=%.0f",
           static_cast<unsigned long long>(passes), static_cast<unsigned long long>(system_calls()),
           per_sim_s, static_cast<unsigned long long>(clock_reads), static_cast<unsigned long long>(polls),
           static_cast<unsigned long long>(sleeps), static_cast<unsigned long long>(reads),
           static_cast<unsigned long long>(writes), static_cast<unsigned long long>(can_frames_in),
           static_cast<unsigned long long>(cpu_us / 1000u), cpu_per_sim_s_ms);
  return text;
}

}  // namespace uno
}  // namespace mb2co
