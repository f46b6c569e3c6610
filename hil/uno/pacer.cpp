#include "pacer.h"

#include <stdio.h>

namespace mb2co {
namespace uno {

Pacer::Pacer(bool paced, uint64_t wall_us, uint64_t sim_us)
    : paced_(paced), offset_us_(wall_us - sim_us), window_wall_us_(wall_us), window_sim_us_(sim_us) {}

uint64_t Pacer::allowed_sim_us(uint64_t sim_us, uint64_t wall_us) {
  if (!paced_) return UINT64_MAX;
  const uint64_t due_us = wall_us - offset_us_;  // where the simulation should stand
  if (due_us > sim_us + kLeadUs) behind_in_window_ = true;
  if (due_us > sim_us + kBehindUs) {  // go on from here
    ++jumps_;
    dropped_us_ += due_us - sim_us;
    moved_at_wall_us_ = wall_us;
    offset_before_us_ = offset_us_;
    held_at_sim_us_ = sim_us;
    held_for_us_ = due_us - sim_us;
    offset_us_ = wall_us - sim_us;
  }
  return wall_us - offset_us_ + kLeadUs;
}

uint64_t Pacer::sim_of(uint64_t wall_us) const {
  if (wall_us >= moved_at_wall_us_) return wall_us > offset_us_ ? wall_us - offset_us_ : 0;
  const uint64_t due_us = wall_us > offset_before_us_ ? wall_us - offset_before_us_ : 0;
  if (due_us <= held_at_sim_us_ || held_for_us_ <= kReplayUs) return due_us;
  // Into the hold-up by (due - held_at) of held_for: as far into kReplayUs.
  return held_at_sim_us_ + (due_us - held_at_sim_us_) * kReplayUs / held_for_us_;
}

uint64_t Pacer::wait_us(uint64_t sim_us, uint64_t wall_us) const {
  if (!paced_) return 0;
  const uint64_t wall_due = offset_us_ + sim_us;  // when the wall reaches the simulation
  return wall_due > wall_us ? wall_due - wall_us : 0;
}

std::string Pacer::slow_report(uint64_t sim_us, uint64_t wall_us) {
  const uint64_t dwall = wall_us - window_wall_us_;
  if (dwall < kWindowUs) return std::string();
  const uint64_t dsim = sim_us - window_sim_us_;
  const bool slow = paced_ && behind_in_window_ && dsim * 100u < dwall * 95u;
  window_wall_us_ = wall_us;
  window_sim_us_ = sim_us;
  behind_in_window_ = false;
  if (!slow || reported_) return std::string();
  reported_ = true;
  char line[200];
  snprintf(line, sizeof line,
           "simavr cannot keep up with real time: %.3f s simulated in %.3f s (%.2fx); the image's "
           "timing is stretched",
           static_cast<double>(dsim) / 1e6, static_cast<double>(dwall) / 1e6,
           static_cast<double>(dsim) / static_cast<double>(dwall));
  return line;
}

}  // namespace uno
}  // namespace mb2co
