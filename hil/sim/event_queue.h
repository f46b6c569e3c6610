// The virtual clock of the line simulator: a queue of timed events in integer
// nanoseconds. Events with the same time run in the order they were
// scheduled (a sequence number breaks ties), so a run is a pure function of
// its inputs and seed: no wall clock, no hash order, no threads.
#pragma once
#include <stdint.h>

#include <vector>

namespace mb2co {
namespace sim {

/// Simulated time in ns since the start of a run (2^64 ns = 584 years).
using SimNs = uint64_t;

constexpr SimNs kNsPerUs = 1000;
constexpr SimNs kNsPerMs = 1000000;
constexpr SimNs kNsPerS = 1000000000;

/// Something that receives events. `code` and `arg` are the receiver's own
/// (which timer, which byte, a generation number to ignore stale events).
class Handler {
 public:
  virtual void on_event(uint32_t code, uint64_t arg) = 0;

 protected:
  ~Handler() = default;
};

/// Min-heap of (time, sequence). Not thread-safe; handlers may schedule
/// new events (at or after now()) from inside on_event.
class EventQueue {
 public:
  SimNs now() const { return now_; }
  /// Schedules `h->on_event(code, arg)` at `t_ns` (clamped to now()).
  void at(SimNs t_ns, Handler* h, uint32_t code, uint64_t arg = 0);
  void after(SimNs delay_ns, Handler* h, uint32_t code, uint64_t arg = 0) {
    at(now_ + delay_ns, h, code, arg);
  }
  /// Runs every event due at or before `t_end_ns`, then sets now() to it.
  void run_until(SimNs t_end_ns);
  /// Events handled so far (for the speed figure).
  uint64_t handled() const { return handled_; }
  bool empty() const { return heap_.empty(); }

 private:
  struct Ev {
    SimNs t;
    uint64_t seq;
    Handler* h;
    uint32_t code;
    uint64_t arg;
  };
  struct Later {
    bool operator()(const Ev& a, const Ev& b) const { return a.t != b.t ? a.t > b.t : a.seq > b.seq; }
  };

  std::vector<Ev> heap_;
  SimNs now_ = 0;
  uint64_t seq_ = 0;
  uint64_t handled_ = 0;
};

}  // namespace sim
}  // namespace mb2co
