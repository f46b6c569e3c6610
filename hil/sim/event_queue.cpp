#include "sim/event_queue.h"

#include <algorithm>

namespace mb2co {
namespace sim {

void EventQueue::push(Heap& heap, const Ev& e) {
  heap.push_back(e);
  std::push_heap(heap.begin(), heap.end(), later);
}

void EventQueue::pop(Heap& heap) {
  std::pop_heap(heap.begin(), heap.end(), later);
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
  push(t - now_ < kNearNs ? near_ : far_, Ev{t, seq_++, h, code, arg});
}

void EventQueue::run_until(SimNs t_end_ns) {
  for (;;) {
    Heap* heap = &near_;
    if (near_.empty() || (!far_.empty() && later(near_.front(), far_.front()))) heap = &far_;
    if (heap->empty() || heap->front().t > t_end_ns) break;
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
