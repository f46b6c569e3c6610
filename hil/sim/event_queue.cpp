#include "sim/event_queue.h"

#include <algorithm>

namespace mb2co {
namespace sim {

// push() and pop() are std::push_heap and std::pop_heap as libstdc++
// writes them (sift up; pop: the hole to a leaf by the earlier child, then
// the last element up from there), with the key compared inline instead of
// through a function pointer. The same steps leave the same layout, which
// matters where two keys are equal (see "Sleeping").
void EventQueue::push(Heap& heap, const Ev& e) {
  heap.push_back(e);
  sift_up(heap, heap.size() - 1, 0, e);
}

void EventQueue::sift_up(Heap& heap, size_t hole, size_t top, const Ev& e) {
  const unsigned __int128 k = key(e);
  while (hole > top) {
    const size_t parent = (hole - 1) / 2;
    if (!(key(heap[parent]) > k)) break;
    heap[hole] = heap[parent];
    hole = parent;
  }
  heap[hole] = e;
}

void EventQueue::pop(Heap& heap) {
  const size_t n = heap.size() - 1;  // the heap after the root left
  if (n > 0) {
    const Ev e = heap[n];
    size_t hole = 0;
    size_t child = 0;
    while (child < (n - 1) / 2) {
      child = 2 * (child + 1);
      if (later(heap[child], heap[child - 1])) --child;
      heap[hole] = heap[child];
      hole = child;
    }
    if ((n & 1) == 0 && child == (n - 2) / 2) {
      child = 2 * (child + 1);
      heap[hole] = heap[child - 1];
      hole = child - 1;
    }
    sift_up(heap, hole, 0, e);
  }
  heap.pop_back();
}

void EventQueue::sift_down_root(Heap& heap) {
  const size_t n = heap.size();
  const Ev e = heap[0];
  size_t hole = 0;
  for (;;) {
    size_t child = 2 * hole + 1;
    if (child >= n) break;
    if (child + 1 < n && later(heap[child], heap[child + 1])) ++child;
    if (!later(e, heap[child])) break;
    heap[hole] = heap[child];
    hole = child;
  }
  heap[hole] = e;
}

void EventQueue::at(SimNs t_ns, Handler* h, uint32_t code, uint64_t arg) {
  const SimNs t = t_ns < now_ ? now_ : t_ns;
  push(t - now_ < kNearNs ? near_ : far_, Ev{t, next_seq(), h, code, arg});
}

void EventQueue::sleep(Sleeper* s, SimNs t_ns, uint32_t code, uint64_t arg) {
  s->sleep_t_ = t_ns < now_ ? now_ : t_ns;
  s->sleep_seq_ = next_seq();
  s->sleep_code_ = code;
  s->sleep_arg_ = arg;
  s->floor_known_ = false;  // its event just ran: its floor moves
  if (!s->asleep_) {
    s->asleep_ = true;
    sleepers_.push_back(s);
  }
  if (s->sleep_t_ < sleepers_min_t_) sleepers_min_t_ = s->sleep_t_;
}

void EventQueue::wake(Sleeper* s) {
  if (!s->asleep_) return;
  s->asleep_ = false;
  s->floor_known_ = false;
  sleepers_.erase(std::find(sleepers_.begin(), sleepers_.end(), s));
  const SimNs t = s->sleep_t_;
  push(t - now_ < kNearNs ? near_ : far_, Ev{t, s->sleep_seq_, s, s->sleep_code_, s->sleep_arg_});
  sleepers_min_t_ = ~SimNs{0};
  for (const Sleeper* o : sleepers_) sleepers_min_t_ = std::min(sleepers_min_t_, o->sleep_t_);
}

bool EventQueue::run_sleepers(SimNs t, uint64_t seq) {
  const auto before = [t, seq](const Sleeper* s) {
    return s->sleep_t_ < t || (s->sleep_t_ == t && s->sleep_seq_ < seq);
  };
  // Occurrences run in place are scheduled in the stretch before the next
  // ordinary event: the odd number below it.
  const uint64_t stretch_seq = seq_ - 1;
  for (;;) {
    // Every occurrence before the earliest wake floor of the sleepers due
    // is idle: run them, up to the next event.
    SimNs floor = ~SimNs{0};
    for (Sleeper* s : sleepers_) {
      s->floor_ = ~SimNs{0};
      if (before(s)) {
        if (!s->floor_known_) {
          s->known_floor_ = s->wake_floor();
          s->floor_known_ = true;
        }
        s->floor_ = s->known_floor_;
      }
      floor = std::min(floor, s->floor_);
    }
    // After a sleeper's first occurrence in place the next ones carry
    // stretch_seq: before (t, seq) when earlier than t, or at t when
    // stretch_seq < seq (the end of a run_until).
    const SimNs stretch_end = (stretch_seq < seq && t != ~SimNs{0}) ? t + 1 : t;
    const SimNs limit = std::min(floor, stretch_end);
    SimNs min_t = ~SimNs{0};
    for (Sleeper* s : sleepers_) {
      if (s->sleep_t_ < floor && before(s)) {
        s->sleep_t_ = s->idle_passes(s->sleep_t_, limit, &handled_);
        s->sleep_seq_ = stretch_seq;
      }
      min_t = std::min(min_t, s->sleep_t_);
    }
    sleepers_min_t_ = min_t;
    if (floor > t) return false;  // none woke before the next event: all ran up to it
    // The sleepers whose next occurrence is due and not idle wake; when
    // none does, the one whose floor stopped the others has nothing due.
    bool woke = false;
    for (size_t k = 0; k < sleepers_.size();) {
      Sleeper* s = sleepers_[k];
      if (before(s) && s->sleep_t_ >= s->floor_) {
        wake(s);
        woke = true;
      } else {
        ++k;
      }
    }
    if (woke) return true;
  }
}

void EventQueue::run_until(SimNs t_end_ns) {
  for (;;) {
    Heap* heap = &near_;
    if (near_.empty() || (!far_.empty() && later(near_.front(), far_.front()))) heap = &far_;
    const bool ends = heap->empty() || heap->front().t > t_end_ns;
    // The sleepers' occurrences before the next event (or up to the end).
    const SimNs until = ends ? t_end_ns : heap->front().t;
    if (sleepers_min_t_ <= until && run_sleepers(until, ends ? ~uint64_t{0} : heap->front().seq)) continue;
    if (ends) break;
    // The root stays in place while its handler runs (see the class comment).
    const Ev e = heap->front();
    now_ = e.t;
    ++handled_;
    again_ = false;
    e.h->on_event(e.code, e.arg);
    if (again_) {
      heap->front().t = again_t_;
      heap->front().seq = again_seq_;
      sift_down_root(*heap);
    } else {
      pop(*heap);
    }
  }
  again_ = false;
  if (t_end_ns > now_) now_ = t_end_ns;
}

}  // namespace sim
}  // namespace mb2co
