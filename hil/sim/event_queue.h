// The virtual clock of the line simulator: a queue of timed events in integer
// nanoseconds. Events with the same time run in the order they were
// scheduled (a sequence number breaks ties), so a run is a pure function of
// its inputs and seed: no wall clock, no hash order, no threads.
#pragma once
#include <stddef.h>
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

/// A handler whose recurring event (a station's firmware pass) may be
/// jumped while it provably does nothing: the queue runs such an occurrence
/// in place (idle_passes()) instead of through its heaps, at the same place in
/// the order (EventQueue, "Sleeping").
class Sleeper : public Handler {
 public:
  /// The earliest time from which an occurrence is not idle (0: the next
  /// one is not: an input came).
  virtual SimNs wake_floor() const = 0;
  /// Runs the idle occurrence at `t_ns` and every next one earlier than
  /// `limit_ns` (their own bookkeeping and random draws, in the order the
  /// events would make them), adding their count to `*count`; returns the
  /// time of the next one (>= limit_ns; each occurrence comes after the one
  /// before). One call per stretch: a station's idle passes in a loop of
  /// their own, not a virtual call each.
  virtual SimNs idle_passes(SimNs t_ns, SimNs limit_ns, uint64_t* count) = 0;
  /// The queue keeps wake_floor() while the sleeper sleeps (it is asked
  /// before every event otherwise). Whoever changes what it depends on (an
  /// input arrives: a CAN frame, a serial character, a button) calls this;
  /// the queue asks again before its next occurrence runs. The sleeper's own
  /// events need not (sleep() and wake() forget the floor). A floor kept
  /// too low only wakes the sleeper early into a heap, where its occurrence
  /// runs as the idle event it is; one kept too high skips work: wrong.
  void floor_moved() { floor_known_ = false; }

 protected:
  ~Sleeper() = default;

 private:
  friend class EventQueue;
  SimNs sleep_t_ = 0;  ///< the next occurrence's key while asleep
  uint64_t sleep_seq_ = 0;
  uint32_t sleep_code_ = 0;
  uint64_t sleep_arg_ = 0;
  bool asleep_ = false;
  bool floor_known_ = false;  ///< known_floor_ is wake_floor() (floor_moved() clears it)
  SimNs known_floor_ = 0;
  SimNs floor_ = 0;  ///< the floor run_sleepers() used last (~0: not due)
};

/// Events in (time, sequence) order. Not thread-safe; handlers may schedule
/// new events (at or after now()) from inside on_event.
///
/// Two min-heaps: events due within kNearNs of when they were scheduled
/// (firmware passes, bytes, frames: a handful) and the rest (cycle starts,
/// timeouts: most of the stale ones). The next event is the earlier of the
/// two roots, so the order is the same as one heap's; the near one stays
/// shallow, which is where the frequent events are.
///
/// Sleeping (a station's idle passes): the handler of the event being
/// handled may call sleep() instead of again_at(). Its next occurrence then
/// waits outside the heaps, keyed as again_at() would have keyed it. Before
/// each event from the heaps, every sleeper's occurrences ordered before it
/// run in place by idle_passes(), each counted in handled(); the first that
/// is not idle (at or after wake_floor()) goes into a heap with its key and
/// runs as an ordinary event. Sequence numbers of scheduled events are
/// even; an occurrence scheduled by an idle one gets the odd number between
/// those scheduled before it and after it (the same for all of one stretch
/// between two ordinary events), so its place among events of the same
/// nanosecond is the one it had with every pass in a heap. Sleepers are
/// moved forward only up to the next ordinary event and the earliest
/// wake_floor(), so a sleeper never runs past an occurrence of another
/// that wakes first.
///
/// The event being handled stays at the root of its heap until its handler
/// returns (every event scheduled meanwhile has a later key, so it never
/// rises above it); then it is removed, or re-keyed in place when the handler
/// called again_at(). That saves a pop and a push for a periodic event (a
/// firmware pass), and orders exactly as at() would: the sequence number is
/// taken when again_at() is called.
class EventQueue {
 public:
  static constexpr SimNs kNearNs = 5 * kNsPerMs;

  SimNs now() const { return now_; }
  /// Schedules `h->on_event(code, arg)` at `t_ns` (clamped to now()).
  void at(SimNs t_ns, Handler* h, uint32_t code, uint64_t arg = 0);
  void after(SimNs delay_ns, Handler* h, uint32_t code, uint64_t arg = 0) {
    at(now_ + delay_ns, h, code, arg);
  }
  /// Only from inside on_event, at most once per call: the event being
  /// handled happens again (same handler, code and arg) at `t_ns` (clamped to
  /// now()). Same order as at(h, code, arg) called at this point.
  void again_at(SimNs t_ns) {
    again_ = true;
    again_t_ = t_ns < now_ ? now_ : t_ns;
    again_seq_ = next_seq();
  }
  /// Only from inside `s`'s on_event, instead of again_at(): the event
  /// happens again at `t_ns` (same key as again_at()), run in place while
  /// idle (see "Sleeping").
  void sleep(Sleeper* s, SimNs t_ns, uint32_t code, uint64_t arg);
  /// A sleeper's next occurrence goes into a heap now (an input came, or
  /// it is powered off: the occurrence then runs as the stale event it is).
  void wake(Sleeper* s);
  /// Runs every event due at or before `t_end_ns`, then sets now() to it.
  void run_until(SimNs t_end_ns);
  /// Events handled so far (for the speed figure).
  uint64_t handled() const { return handled_; }
  bool empty() const { return near_.empty() && far_.empty(); }
  /// Events scheduled and not yet handled (stale ones included).
  size_t size() const { return near_.size() + far_.size(); }

 private:
  struct Ev {
    SimNs t;
    uint64_t seq;
    Handler* h;
    uint32_t code;
    uint64_t arg;
  };
  /// (t, seq) as one number: compared without a branch (heap order is hard
  /// to predict).
  static unsigned __int128 key(const Ev& e) { return (static_cast<unsigned __int128>(e.t) << 64) | e.seq; }
  static bool later(const Ev& a, const Ev& b) { return key(a) > key(b); }
  using Heap = std::vector<Ev>;
  uint64_t next_seq() {
    const uint64_t n = seq_;
    seq_ += 2;
    return n;
  }
  /// Runs the sleepers' occurrences ordered before (t, seq) in place;
  /// true when one woke into a heap (the next event may be it).
  bool run_sleepers(SimNs t, uint64_t seq);
  static void push(Heap& heap, const Ev& e);
  static void pop(Heap& heap);
  /// Moves `e` from `hole` up towards `top` to its place by key.
  static void sift_up(Heap& heap, size_t hole, size_t top, const Ev& e);
  /// Restores the heap order after the root's key grew.
  static void sift_down_root(Heap& heap);

  Heap near_;
  Heap far_;
  std::vector<Sleeper*> sleepers_;
  SimNs sleepers_min_t_ = ~SimNs{0};  ///< the earliest sleeper's next occurrence
  SimNs now_ = 0;
  uint64_t seq_ = 2;  ///< even: see "Sleeping"
  uint64_t handled_ = 0;
  bool again_ = false;  ///< again_at() was called by the handler running
  SimNs again_t_ = 0;
  uint64_t again_seq_ = 0;
};

}  // namespace sim
}  // namespace mb2co
