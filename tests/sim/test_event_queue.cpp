// The event queue's sleeping occurrences (EventQueue, "Sleeping") keep their
// place among events of the same nanosecond: a run where a periodic handler
// sleeps over its idle occurrences handles everything in the order of the
// run where each occurrence goes through the heaps (again_at), with events
// scheduled on the very nanoseconds of its occurrences, from handlers that
// run on them, and inputs that wake it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

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
  SimNs idle_passes(SimNs t, SimNs limit, uint64_t* count) override {
    do {
      ++*count;
      log_ += "i" + std::to_string(t) + " ";
      t += 3 + rng_.below(2);
    } while (t < limit);
    return t;
  }
  /// An input; `wake_now`: the sleeper is also woken at once (as a station
  /// is at power off) instead of by its wake floor at its next tick.
  void set_input(bool wake_now) {
    input = true;
    floor_moved();
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

/// Ticks every 10 ns, idle before `wake_at`; counts the queue's questions
/// for its wake floor and its busy ticks.
class CountingSleeper final : public Sleeper {
 public:
  explicit CountingSleeper(EventQueue& q) : q_(q) {}
  void on_event(uint32_t, uint64_t) override {
    if (q_.now() >= wake_at) {
      busy.push_back(q_.now());
      wake_at = ~SimNs{0};
    }
    q_.sleep(this, q_.now() + 10, 0, 0);
  }
  SimNs wake_floor() const override {
    ++asked;
    return wake_at;
  }
  SimNs idle_passes(SimNs t, SimNs limit, uint64_t* count) override {
    const uint64_t n = (limit - t + 9) / 10;  // the ticks from t before limit (t < limit)
    *count += n;
    return t + 10 * n;
  }

  SimNs wake_at = ~SimNs{0};
  mutable int asked = 0;
  std::vector<SimNs> busy;

 private:
  EventQueue& q_;
};

/// An event every ns; at 503 the sleeper's input comes.
class Input final : public Handler {
 public:
  Input(EventQueue& q, CountingSleeper& s, bool tell) : q_(q), s_(s), tell_(tell) {}
  void on_event(uint32_t, uint64_t) override {
    if (q_.now() == 503) {
      s_.wake_at = 0;
      if (tell_) s_.floor_moved();
    }
    if (q_.now() < 1000) q_.after(1, this, 0);
  }

 private:
  EventQueue& q_;
  CountingSleeper& s_;
  bool tell_;
};

/// 1,000 ns of the sleeper among an event every ns, its input at 503 (told
/// by floor_moved() or not); the sleeper as it ends.
struct InputRun {
  int asked;
  std::vector<SimNs> busy;
};
InputRun run_with_input(bool tell) {
  EventQueue q;
  CountingSleeper s(q);
  Input input(q, s, tell);
  q.at(0, &s, 0);
  q.at(0, &input, 0);
  q.run_until(1000);
  return InputRun{s.asked, s.busy};
}

TEST(EventQueue, AWakeFloorIsKeptUntilItMoves) {
  const InputRun r = run_with_input(true);
  // Asked after its first event, after floor_moved() and after the busy
  // tick (its own event), not before each of the 1,000 other events; the
  // input is seen at the first tick after it.
  EXPECT_EQ(r.asked, 3);
  EXPECT_EQ(r.busy, (std::vector<SimNs>{510}));
}

TEST(EventQueue, AnInputNotToldIsNotSeenWhileTheFloorIsKept) {
  // The contract's other side: a change of the floor without floor_moved()
  // stays unseen (why every input of a station tells it).
  const InputRun r = run_with_input(false);
  EXPECT_EQ(r.asked, 1);
  EXPECT_TRUE(r.busy.empty());
}

}  // namespace
}  // namespace sim
}  // namespace mb2co
