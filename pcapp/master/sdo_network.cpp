#include "sdo_network.h"

#include <algorithm>
#include <cstring>

namespace mb2co {
namespace master {

SdoNetwork::SdoNetwork(uint32_t timeout_us, uint16_t heartbeat_ms)
    : timeout_us_(timeout_us), heartbeat_ms_(heartbeat_ms) {
  monitors_.set_listener(canopen::MonitorListener{&SdoNetwork::on_monitor, this});
}

void SdoNetwork::queue(Transfer* t) {
  Node& n = nodes_[t->node];
  if (!n.used) {
    n.used = true;
    used_.insert(std::lower_bound(used_.begin(), used_.end(), t->node), t->node);
    n.client.init(t->node);
    n.client.set_timeout_us(timeout_us_);
    // The producer time is the node's business; only the consumer time counts.
    if (heartbeat_ms_ && monitors_.monitor(t->node))
      monitors_.monitor(t->node)->watch_heartbeat(t->node, 1, heartbeat_ms_);
  }
  n.queue.push_back(t);
  ++pending_;
  if (sink_.send) start_next(t->node, now_us_, sink_);
}

void SdoNetwork::progress(uint8_t node, uint32_t* moved, uint32_t* size) const {
  const Node& n = nodes_[node];
  const bool running = !n.queue.empty() && n.client.busy();
  *moved = running ? n.client.transferred() : 0;
  *size = running && n.client.size_known() ? n.client.size() : 0;
}

canopen::SdoAbort SdoNetwork::collect(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n) {
  auto* t = static_cast<Transfer*>(ctx);
  if (t->write) return t->write(data, n);                       // offsets come in order, from 0
  if (offset != t->data.size()) return canopen::kAbortGeneral;  // never: offsets come in order
  t->data.insert(t->data.end(), data, data + n);
  return canopen::kSdoOk;
}

canopen::SdoAbort SdoNetwork::supply(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
  auto* t = static_cast<Transfer*>(ctx);
  if (static_cast<size_t>(offset) + n > t->data.size()) return canopen::kAbortGeneral;
  std::memcpy(buf, t->data.data() + offset, n);
  return canopen::kSdoOk;
}

void SdoNetwork::start_next(uint8_t id, uint32_t now_us, const CanSink& sink) {
  Node& n = nodes_[id];
  while (!n.queue.empty() && !n.client.busy()) {
    Transfer* t = n.queue.front();
    if (t->started || t->finished) return;  // running (or being finished)
    if (t->not_before_us != 0 && !time_reached(now_us, t->not_before_us)) return;  // a poll's pause
    if (!t->started) t->started_us = now_us;  // a transfer started over keeps its start
    t->started = true;
    n.heard_serving = false;
    n.client.set_timeout_us(t->timeout_us ? t->timeout_us : timeout_us_);
    n.client.set_timeout_abort_sent(!t->probe);
    bool started;
    if (t->upload) {
      t->data.clear();
      started =
          n.client.start_upload(t->index, t->sub, t->mode, canopen::SdoData{&SdoNetwork::collect, nullptr, t},
                                t->max_bytes, now_us, sink);
    } else {
      started = n.client.start_download(t->index, t->sub, t->mode,
                                        canopen::SdoData{nullptr, &SdoNetwork::supply, t},
                                        static_cast<uint32_t>(t->data.size()), now_us, sink);
    }
    if (started && n.client.busy()) return;
    finish_front(id, now_us, sink);  // refused at once (or done without an answer)
  }
}

bool SdoNetwork::ask_again(uint8_t id, uint32_t now_us, const CanSink& sink) {
  Node& n = nodes_[id];
  Transfer* t = n.queue.front();
  // Our timeout, or the server's (05040000h from it: it waited for a
  // request of ours that did not come).
  const bool timed_out =
      n.client.status() == canopen::SdoClient::kFailed && n.client.result() == canopen::kAbortTimeout;
  if (!timed_out || !n.heard_serving || t->asked_again || t->probe) return false;
  if (t->write && n.client.transferred() != 0) return false;  // those bytes are the caller's now
  t->asked_again = true;
  t->started = false;  // still at the front: start_next starts it again
  // Not at once: the timeout is a whole number of ms, as the neighbours'
  // periods are, and a request sent exactly -t after the lost one met the
  // same neighbour's frames again (measure-sdo-loss.sh: lost twice).
  t->not_before_us = (now_us + kAskAgainPauseUs) | 1u;
  start_next(id, now_us, sink);
  return true;
}

void SdoNetwork::finish_front(uint8_t id, uint32_t now_us, const CanSink& sink) {
  if (ask_again(id, now_us, sink)) return;
  Node& n = nodes_[id];
  Transfer* t = n.queue.front();
  n.queue.pop_front();
  t->finished = true;
  t->ended_us = now_us;
  t->bytes = n.client.transferred();
  if (n.client.status() == canopen::SdoClient::kDone) {
    t->result = canopen::kSdoOk;
  } else {
    t->result = n.client.status() == canopen::SdoClient::kFailed ? n.client.result() : canopen::kAbortGeneral;
    t->by_server = n.client.aborted_by_server();
  }
  t->crc = n.client.crc_used();
  --pending_;
  if (t->on_done) t->on_done(*t);
  start_next(id, now_us, sink);
}

void SdoNetwork::on_monitor(void* ctx, uint8_t node, canopen::MonitorEvent e, uint8_t, uint8_t) {
  // Only noted here: the listener runs inside the monitor's own call.
  if (e == canopen::kMonitorNodeLost) static_cast<SdoNetwork*>(ctx)->lost_.push_back(node);
}

void SdoNetwork::end_queue(uint8_t id, size_t from, canopen::SdoAbort code, bool node_lost, bool notify) {
  Node& n = nodes_[id];
  while (n.queue.size() > from) {
    Transfer* t = n.queue[from];
    n.queue.erase(n.queue.begin() + static_cast<long>(from));
    t->finished = true;
    t->result = code;
    t->node_lost = node_lost;
    t->ended_us = now_us_;
    --pending_;
    if (notify && t->on_done) t->on_done(*t);
  }
}

void SdoNetwork::drop_queued(uint8_t node, canopen::SdoAbort code) {
  const Node& n = nodes_[node];
  const bool running = !n.queue.empty() && n.queue.front()->started;  // it ends on its own
  end_queue(node, running ? 1 : 0, code, false, false);
}

void SdoNetwork::abort_all(canopen::SdoAbort code, const CanSink& sink) {
  for (const uint8_t id : used_) {  // end_queue notifies no one: used_ stays as it is
    Node& n = nodes_[id];
    if (n.client.busy()) n.client.abort(code, sink);
    end_queue(id, 0, code, false, false);
  }
}

bool SdoNetwork::cancel(Transfer* t, canopen::SdoAbort code, const CanSink& sink) {
  Node& n = nodes_[t->node & 0x7F];
  for (size_t i = 0; i < n.queue.size(); ++i) {
    if (n.queue[i] != t) continue;
    const bool running = i == 0 && t->started && n.client.busy();
    if (running) n.client.abort(code, sink);
    n.queue.erase(n.queue.begin() + static_cast<long>(i));
    t->finished = true;
    t->result = code;
    t->ended_us = now_us_;
    --pending_;
    if (i == 0) start_next(t->node, now_us_, sink);
    return true;
  }
  return false;
}

void SdoNetwork::on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink) {
  now_us_ = now_us;
  sink_ = sink;
  if (f.extended()) return;
  // A heartbeat (700h + n, its NMT state in byte 0): 05h operational, 7Fh
  // pre-operational, the states in which a node serves SDO (CiA 301).
  if (f.id > 0x700 && f.id <= 0x77F && !f.rtr() && f.dlc >= 1) {
    const uint8_t state = f.data[0] & 0x7F;
    if (state == 0x05 || state == 0x7F) nodes_[f.id - 0x700].heard_serving = true;
  }
  if (heartbeat_ms_ && monitors_.on_frame(f, now_us)) return;
  if (f.id < 0x581 || f.id > 0x5FF) return;
  const uint8_t id = static_cast<uint8_t>(f.id - 0x580);
  Node& n = nodes_[id];
  if (!n.used || n.queue.empty()) return;
  n.client.on_frame(f, now_us, sink);
  if (!n.client.busy()) finish_front(id, now_us, sink);
}

void SdoNetwork::process(uint32_t now_us, const CanSink& sink) {
  now_us_ = now_us;
  sink_ = sink;
  if (heartbeat_ms_) monitors_.process(now_us, sink);
  for (uint8_t id : lost_) {
    Node& n = nodes_[id];
    if (n.queue.empty()) continue;
    // The watchdog ends the running transfer and everything queued behind
    // it: the node is gone, asking it more would only wait for timeouts.
    if (n.client.busy()) n.client.abort(canopen::kAbortTimeout, sink);
    end_queue(id, 0, canopen::kAbortTimeout, true, true);
  }
  lost_.clear();
  // By index: an on_done may queue a transfer for a new node, which
  // inserts into used_ (a node then visited twice does no harm).
  for (size_t i = 0; i < used_.size(); ++i) {
    const uint8_t id = used_[i];
    Node& n = nodes_[id];
    if (!n.queue.empty() && n.client.busy()) {
      n.client.process(now_us, sink);
      if (!n.client.busy()) finish_front(id, now_us, sink);
    } else {
      start_next(id, now_us, sink);
    }
  }
}

void SdoNetwork::next_deadline(NextDeadline& d) const {
  if (heartbeat_ms_) monitors_.next_deadline(d);
  for (const uint8_t id : used_) {
    const Node& n = nodes_[id];
    if (n.queue.empty()) continue;
    const Transfer* front = n.queue.front();
    if (n.client.busy())
      n.client.next_deadline(d);
    else if (front->not_before_us != 0 && !front->started)
      d.at(front->not_before_us);  // a poll's pause
    else
      d.now();  // a queued transfer waits to start
  }
}

}  // namespace master
}  // namespace mb2co
