// The CSV of every event of a run: one line per event, in the order they
// happened (the event queue's order), integers only, so the same seed gives
// the same bytes. Columns: t_ns,run,station,event,detail (station = node id,
// empty for the bus; detail holds key=value pairs separated by spaces).
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <string>

#include "sim/can_trace.h"
#include "sim/event_queue.h"

namespace mb2co {
namespace sim {

class EventLog {
 public:
  static const char* header() { return "t_ns,run,station,event,detail\n"; }
  /// A disabled log formats nothing: its writers check enabled() before
  /// they build a line (mb2co-lab without --events, benchmarks).
  explicit EventLog(bool enabled = true) : enabled_(enabled) {}
  bool enabled() const { return enabled_; }
  /// Name of the run in progress (column 2), e.g. "stop2" or "latency-125k-canopen".
  /// A new run restarts the simulated clock: the CAN trace continues after it.
  void set_run(const std::string& run) {
    run_ = run;
    if (can_trace_ != nullptr) can_trace_->start_run();
  }
  /// Where the lines built with this log write the frames of their bus
  /// (candump -L); nullptr: nowhere. Not owned; must outlive the runs.
  void set_can_trace(CanTrace* trace) { can_trace_ = trace; }
  CanTrace* can_trace() const { return can_trace_; }
  /// station < 0: the bus / the line as a whole.
  void add(SimNs t, int station, const char* event, const std::string& detail);
  const std::string& text() const { return text_; }
  uint64_t lines() const { return lines_; }

 private:
  bool enabled_;
  std::string run_;
  std::string text_;
  CanTrace* can_trace_ = nullptr;
  uint64_t lines_ = 0;
};

/// Appends bytes as upper-case hex pairs separated by spaces ("0A FF"): the
/// data columns of the log, without a printf per byte.
void append_hex_bytes(std::string* out, const uint8_t* d, size_t n);

/// printf into a std::string.
std::string strf(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace sim
}  // namespace mb2co
