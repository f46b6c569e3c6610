#include "status_view.h"

namespace mb2co {
namespace pcapp {

namespace {
const char kClearLine[] = "\r\033[K";
}

void StatusView::event(double t_s, const std::string& text) {
  if (line_shown_) std::fputs(kClearLine, out_);
  line_shown_ = false;
  std::fprintf(out_, "%.3f %s\n", t_s, text.c_str());
  std::fflush(out_);
}

void StatusView::status(const std::string& line) {
  if (!terminal_) return;
  std::fputs(kClearLine, out_);
  std::fputs(line.c_str(), out_);
  std::fflush(out_);
  line_shown_ = true;
}

void StatusView::finish() {
  if (line_shown_) std::fputc('\n', out_);
  line_shown_ = false;
  std::fflush(out_);
}

}  // namespace pcapp
}  // namespace mb2co
