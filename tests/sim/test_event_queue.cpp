// The event queue's sleeping occurrences (EventQueue, "Sleeping") keep their
// place among events of the same nanosecond: a run where a periodic handler
// sleeps over its idle occurrences handles everything in the order of the
// run where each occurrence goes through the heaps (again_at), with events
// scheduled on the very nanoseconds of its occurrences, from handlers that
// run on them, and inputs that wake it.
#include <gtest/gtest.h>

#include <string>

#include "sim/event_queue.h"
#include "sim/rng.h"

namespace mb2co {
namespace sim {
namespace {

/// Ticks every 3 or 4 ns (a random draw per tick, as a station's jitter);
/// a tick is busy while `input` is set (then it clears it) or from `wake_at`
/// on, idle otherwise.
class Ticker final : public Sleeper {
 public:
  Ticker(EventQueue& q, std::string& log, bool sleeps, uint64_t seed)
      : q_(q), log_(log), sleeps_(sleeps), rng_(seed) {}
  void start(SimNs t) { q_.at(t, this, 0); }
  void on_event(uint32_t, uint64_t) override {
    const SimNs t = q_.now();
    const bool busy = input || t >= wake_at;
    log_ += (busy ? "B" : "i") + std::to_string(t) + " ";
    if (busy) {
      input = false;
      wake_at = t + 40;  // a deadline further on
    }
    const SimNs next = t + 3 + rng_.below(2);
    if (sleeps_)
      q_.sleep(this, next, 0, 0);
    else
      q_.again_at(next);
  }
  SimNs wake_floor() const override { return input ? 0 : wake_at; }
  SimNs idle_pass(SimNs t) override {
    log_ += "i" + std::to_string(t) + " ";
    return t + 3 + rng_.below(2);
  }
  /// An input; `wake_now`: the sleeper is also woken at once (as a station
  /// is at power off) instead of by its wake floor at its next tick.
  void set_input(bool wake_now) {
    input = true;
    if (sleeps_ && wake_now) q_.wake(this);
  }

  bool input = false;
  SimNs wake_at = 0;

 private:
  EventQueue& q_;
  std::string& log_;
  bool sleeps_;
  Rng rng_;
};

/// Ordinary events on the ticks' nanoseconds: each logs itself and
/// schedules the next of its chain 0..8 ns ahead, one in ten an input to
/// the ticker.
class Prober final : public Handler {
 public:
  Prober(EventQueue& q, std::string& log, Ticker& ticker, uint64_t seed)
      : q_(q), log_(log), ticker_(ticker), rng_(seed) {}
  void on_event(uint32_t code, uint64_t arg) override {
    log_ += "p" + std::to_string(arg) + "@" + std::to_string(q_.now()) + " ";
    if (code == 1) ticker_.set_input(arg % 2 == 1);
    if (q_.now() > 3000) return;
    q_.after(rng_.below(9), this, rng_.below(10) == 0 ? 1 : 0, next_id_++);
  }

 private:
  EventQueue& q_;
  std::string& log_;
  Ticker& ticker_;
  Rng rng_;
  uint64_t next_id_ = 1;
};

std::string run(bool sleeps, uint64_t seed) {
  EventQueue q;
  std::string log;
  Ticker ticker(q, log, sleeps, seed);
  Prober prober(q, log, ticker, seed + 1000);
  ticker.start(1);
  for (SimNs t = 0; t < 4; ++t) q.at(t, &prober, 0, 0);  // four chains
  q.run_until(1000);
  log += "| ";  // a stop in the middle: run_until's end runs the sleeper up to it
  q.run_until(3100);
  return log + "handled " + std::to_string(q.handled());
}

TEST(EventQueue, SleepingKeepsTheOrderOfEveryEventOnTheSameNanosecond) {
  for (uint64_t seed = 1; seed <= 40; ++seed) {
    const std::string eager = run(false, seed);
    ASSERT_EQ(eager, run(true, seed)) << "seed " << seed;
    // The runs exercise it: ticks idle and busy, probes on tick nanoseconds.
    EXPECT_NE(eager.find(" i"), std::string::npos);
    EXPECT_NE(eager.find(" B"), std::string::npos);
  }
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
