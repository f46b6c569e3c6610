// What the user sees. On a terminal: one live status line, redrawn in
// place, with events printed above it. Otherwise (a pipe, a file, a test):
// plain log lines, one per event, "<seconds> <event>".
#pragma once
#include <cstdio>
#include <string>

namespace mb2co {
namespace pcapp {

class StatusView {
 public:
  /// `terminal`: draw the live line (normally isatty(fileno(out))).
  StatusView(std::FILE* out, bool terminal) : out_(out), terminal_(terminal) {}

  /// An event line, stamped with `t_s` seconds since the start; flushed.
  void event(double t_s, const std::string& text);
  /// The live line (terminal only; ignored otherwise).
  void status(const std::string& line);
  /// Leaves the live line in place and moves below it.
  void finish();
  bool terminal() const { return terminal_; }

 private:
  std::FILE* out_;
  bool terminal_;
  bool line_shown_ = false;
};

}  // namespace pcapp
}  // namespace mb2co
