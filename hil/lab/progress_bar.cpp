#include "progress_bar.h"

#include <cmath>

namespace mb2co {
namespace lab {

void ProgressBar::show(const std::string& stage, double fraction, uint64_t now_ns) {
  if (out_ == nullptr) return;
  fraction = fraction < 0 ? 0 : fraction > 1 ? 1 : fraction;
  const int percent = static_cast<int>(std::lround(fraction * 100));
  const bool new_stage = stage != stage_;
  const bool at_end = fraction >= 1 && percent != percent_;
  const bool due = percent != percent_ && now_ns - drawn_ns_ >= kMinRedrawNs;
  if (!new_stage && !at_end && !due) return;
  const int width = 30;
  std::string bar(static_cast<size_t>(std::lround(fraction * width)), '#');
  bar.resize(width, ' ');
  std::fprintf(out_, "\r[%s] %3d%% %-28s", bar.c_str(), percent, stage.c_str());
  std::fflush(out_);
  stage_ = stage;
  percent_ = percent;
  drawn_ns_ = now_ns;
  ++redraws_;
}

void ProgressBar::clear() {
  if (out_ == nullptr) return;
  std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  stage_.clear();
  percent_ = -1;
}

}  // namespace lab
}  // namespace mb2co
