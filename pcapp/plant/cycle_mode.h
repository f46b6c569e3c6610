// What one control cycle does with the registers it read, independent of how
// they travel: the station (plant + controller) and the latency lab are two
// modes behind this interface. Pure C++ (no Qt, no I/O), so the benchmark
// measures exactly the per-cycle work the app does besides the serial wait.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "register_layout.h"
#include "station_io.h"

namespace mb2co {
namespace pcapp {

/// One log cell: a number, or a static text when `text` is not null.
struct LogValue {
  int64_t number = 0;
  const char* text = nullptr;
};

class CycleMode {
 public:
  virtual ~CycleMode() = default;

  /// Fields the mode cannot work without / shows when mapped / writes.
  virtual std::vector<Field> required_reads() const = 0;
  virtual std::vector<Field> optional_reads() const = 0;
  virtual std::vector<Field> writes() const = 0;

  /// One cycle on a fresh read; puts the values to write into `out`.
  virtual void step(const RegisterImage& in, RegisterImage& out) = 0;
  /// One cycle without a link (the plant keeps its time, nothing moves).
  virtual void step_offline() = 0;
  /// The link is gone: make everything safe now.
  virtual void link_lost() = 0;
  /// The values that leave the gateway safe (written at shutdown).
  virtual void safe_outputs(RegisterImage& out) const = 0;
  /// True when the mode has done what it was asked (the app then exits).
  virtual bool done() const { return false; }

  /// Lines ('\n'-separated) for the event log when the last step changed
  /// something that matters (buttons, state, stop cause, a measured press),
  /// else empty.
  virtual std::string take_event() = 0;
  /// The terminal's status line (without time and link part).
  virtual std::string status() const = 0;
  /// Log columns after the common ones; same count and order every cycle.
  virtual std::vector<const char*> column_names() const = 0;
  virtual void columns(std::vector<LogValue>& out) const = 0;
  /// Summary printed at exit (one line, may be empty).
  virtual std::string summary() const = 0;
};

}  // namespace pcapp
}  // namespace mb2co
