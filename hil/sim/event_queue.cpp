#include "sim/event_queue.h"

#include <algorithm>

namespace mb2co {
namespace sim {

void EventQueue::at(SimNs t_ns, Handler* h, uint32_t code, uint64_t arg) {
  heap_.push_back(Ev{t_ns < now_ ? now_ : t_ns, seq_++, h, code, arg});
  std::push_heap(heap_.begin(), heap_.end(), Later());
}

void EventQueue::run_until(SimNs t_end_ns) {
  while (!heap_.empty() && heap_.front().t <= t_end_ns) {
    std::pop_heap(heap_.begin(), heap_.end(), Later());
    const Ev e = heap_.back();
    heap_.pop_back();
    now_ = e.t;
    ++handled_;
    e.h->on_event(e.code, e.arg);
  }
  if (t_end_ns > now_) now_ = t_end_ns;
}

}  // namespace sim
}  // namespace mb2co
