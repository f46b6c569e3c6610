#include "gateway_network.h"

#include <time.h>

#include <cstdio>

#include "canopen/clock.h"

namespace mb2co {
namespace master {

namespace {

/// How long to wait before asking a busy gateway (exception 06) again.
const uint32_t kBusyPauseMs = 5;

std::string exception_text(modbus::Exception e) {
  char b[64];
  std::snprintf(b, sizeof b, "the gateway answered exception %02Xh", static_cast<unsigned>(e));
  return b;
}

/// Exception 01: the gateway has no network access at all.
std::string no_network_access(const GatewayChannel& channel) {
  return exception_text(modbus::Exception::kIllegalFunction) + ": " + channel.where() +
         " has no FC 2Bh/0Dh (CANopen network access is off or not built in)";
}

}  // namespace

Status gateway_nmt(GatewayChannel& channel, uint8_t slave, uint32_t timeout_ms, uint8_t command,
                   uint8_t node) {
  uint8_t request[modbus::kMaxAduBytes];
  const uint16_t n = modbus::build_net_nmt(request, sizeof request, slave, node, command);
  modbus::NetResponse r{};
  const GatewayChannel::Exchange got = channel.exchange(request, n, timeout_ms, &r);
  if (got.outcome == GatewayChannel::Outcome::kInterrupted) return Status::failure("interrupted");
  if (got.outcome != GatewayChannel::Outcome::kAnswered) return got.status;
  if (r.exception == modbus::Exception::kIllegalFunction) return Status::failure(no_network_access(channel));
  if (r.exception != modbus::Exception::kNone)
    return Status::failure(exception_text(r.exception) + " to the NMT command (" + channel.where() + ")");
  return Status::ok();
}

GatewayNetwork::GatewayNetwork(GatewayChannel& channel, uint8_t slave, uint32_t response_timeout_ms)
    : channel_(channel), slave_(slave), response_timeout_ms_(response_timeout_ms) {}

uint32_t GatewayNetwork::now_us() const {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000u +
                               static_cast<uint64_t>(ts.tv_nsec) / 1000u);
}

void GatewayNetwork::queue(Transfer* t) {
  ++pending_;
  if (!link_) {  // the gateway is gone: nothing would come back
    link_down(t, link_.message());
    return;
  }
  queues_[t->node & 0x7F].push_back(t);
}

void GatewayNetwork::progress(uint8_t node, uint32_t* moved, uint32_t* size) const {
  const bool running = running_ != nullptr && running_->node == node;
  *moved = running ? moved_ : 0;
  *size = running ? size_ : 0;
}

void GatewayNetwork::drop_queued(uint8_t node, canopen::SdoAbort code) {
  std::deque<Transfer*>& q = queues_[node & 0x7F];
  while (!q.empty()) {
    Transfer* t = q.front();
    q.pop_front();
    t->finished = true;
    t->result = code;
    --pending_;
  }
}

void GatewayNetwork::abort_all(canopen::SdoAbort code) {
  // The running transfer (if any) ends at its next request: run() sees it
  // finished. The gateway's own SDO client ends a remote transfer left
  // half-way by its timeout.
  if (running_ && !running_->finished) {
    running_->finished = true;
    running_->result = code;
    --pending_;
  }
  for (uint8_t id = 0; id <= 127; ++id) drop_queued(id, code);
}

void GatewayNetwork::finish(Transfer* t, canopen::SdoAbort result, bool by_server) {
  if (t->finished) return;  // ended by abort_all meanwhile
  t->finished = true;
  t->result = result;
  t->by_server = by_server;
  t->ended_us = now_us();
  --pending_;
  if (t->on_done) t->on_done(*t);
}

void GatewayNetwork::refuse(Transfer* t, const std::string& why) {
  t->gateway_error = why;
  finish(t, canopen::kAbortGeneral, true);
}

void GatewayNetwork::link_down(Transfer* t, const std::string& why) {
  if (link_) link_ = Status::failure(why);
  t->gateway_error = why;
  t->link_down = true;
  finish(t, canopen::kAbortGeneral, false);
  // Every other transfer would only wait out the same silence.
  for (std::deque<Transfer*>& q : queues_) {
    while (!q.empty()) {
      Transfer* next = q.front();
      q.pop_front();
      next->gateway_error = why;
      next->link_down = true;
      finish(next, canopen::kAbortGeneral, false);
    }
  }
}

void GatewayNetwork::tick(ProgressHook* progress) {
  if (!progress) return;
  const uint32_t now = now_us();
  if (time_reached(now, progress->next_us())) progress->update(now);
}

GatewayNetwork::Step GatewayNetwork::ask(Transfer* t, const uint8_t* request, uint16_t length,
                                         modbus::NetResponse* r) {
  const uint32_t start = now_us();
  for (;;) {
    tick(progress_);
    if (t->finished) return Step::kInterrupted;  // abort_all from a callback
    const GatewayChannel::Exchange got = channel_.exchange(request, length, response_timeout_ms_, r);
    switch (got.outcome) {
      case GatewayChannel::Outcome::kInterrupted:
        return Step::kInterrupted;
      case GatewayChannel::Outcome::kNoAnswer:
      case GatewayChannel::Outcome::kBadAnswer:
      case GatewayChannel::Outcome::kIoError:
        link_down(t, got.status.message());
        return Step::kFailed;
      case GatewayChannel::Outcome::kAnswered:
        break;
    }
    if (r->exception == modbus::Exception::kNone) return Step::kDone;
    if (r->abort_code != 0) {
      // The gateway's client timing out is silence of the node, as when our
      // own client times out; every other code is the node's (or the
      // gateway's client's) refusal.
      const canopen::SdoAbort code = static_cast<canopen::SdoAbort>(r->abort_code);
      finish(t, code, code != canopen::kAbortTimeout);
      return Step::kFailed;
    }
    if (r->exception == modbus::Exception::kServerDeviceBusy &&
        now_us() - start < response_timeout_ms_ * 1000u) {
      timespec pause = {0, static_cast<long>(kBusyPauseMs) * 1000000L};
      nanosleep(&pause, nullptr);  // pacing a retry, not synchronisation
      continue;
    }
    if (r->exception == modbus::Exception::kIllegalFunction) {
      link_down(t, no_network_access(channel_));
      return Step::kFailed;
    }
    refuse(t, exception_text(r->exception) +
                  (r->exception == modbus::Exception::kIllegalDataValue   ? " (request refused as malformed)"
                   : r->exception == modbus::Exception::kServerDeviceBusy ? " (busy for too long)"
                                                                          : ""));
    return Step::kFailed;
  }
}

GatewayNetwork::Step GatewayNetwork::upload(Transfer* t) {
  t->data.clear();
  uint8_t request[modbus::kMaxAduBytes];
  uint32_t start = 0;
  for (;;) {
    if (start > 0xFFFFu) {
      refuse(t, "object longer than 65535 bytes: a gateway reads at most that much (use SocketCAN)");
      return Step::kFailed;
    }
    const uint16_t n = modbus::build_net_upload(request, sizeof request, slave_, t->node, t->index, t->sub,
                                                static_cast<uint16_t>(start), 0);
    modbus::NetResponse r{};
    const Step s = ask(t, request, n, &r);
    if (s != Step::kDone) return s;
    const modbus::NetMessage& m = r.message;
    // The bounds of our own client (sdo_client.h): a size above max_bytes,
    // or bytes beyond it, end the transfer with 05040005h. The gateway's
    // client is not told (FC 2Bh has no abort); it ends the remote
    // transfer by its own timeout.
    if (m.object_size > t->max_bytes || m.data_length > t->max_bytes - start) {
      finish(t, canopen::kAbortOutOfMemory, false);
      return Step::kFailed;
    }
    if (t->write) {
      const canopen::SdoAbort code = t->write(m.data, m.data_length);
      if (code != canopen::kSdoOk) {
        finish(t, code, false);
        return Step::kFailed;
      }
    } else {
      t->data.insert(t->data.end(), m.data, m.data + m.data_length);
    }
    start += m.data_length;
    moved_ = start;
    t->bytes = start;
    size_ = m.object_size;
    // The last window has "more follows" clear and reaches the object's
    // size; either one not yet means another window.
    if (!m.more_follows && start >= m.object_size) break;
    if (m.data_length == 0) {
      refuse(t, "the gateway sent an empty window with more to follow");
      return Step::kFailed;
    }
  }
  finish(t, canopen::kSdoOk, false);
  return Step::kDone;
}

GatewayNetwork::Step GatewayNetwork::download(Transfer* t) {
  const size_t total = t->data.size();
  // A part's starting address is 16 bits: the last part starts at 65535 at most.
  size_t last_start = 0;
  while (total - last_start > modbus::net::kMaxSdoData) last_start += modbus::net::kMaxPartBytes;
  if (last_start > 0xFFFFu) {
    refuse(t, "object longer than 65535 bytes: a gateway writes at most that much (use SocketCAN)");
    return Step::kFailed;
  }
  size_ = static_cast<uint32_t>(total);
  uint8_t request[modbus::kMaxAduBytes];
  size_t start = 0;
  do {
    const size_t left = total - start;
    // A last part of up to 237 bytes; parts before it of whole segments.
    const uint16_t count =
        static_cast<uint16_t>(left <= modbus::net::kMaxSdoData ? left : modbus::net::kMaxPartBytes);
    const bool more = start + count < total;
    const uint16_t n = modbus::build_net_download(request, sizeof request, slave_, t->node, t->index, t->sub,
                                                  static_cast<uint32_t>(total), static_cast<uint16_t>(start),
                                                  t->data.data() + start, count, more);
    modbus::NetResponse r{};
    const Step s = ask(t, request, n, &r);
    if (s != Step::kDone) return s;
    start += count;
    moved_ = static_cast<uint32_t>(start);
    t->bytes = moved_;
  } while (start < total);
  finish(t, canopen::kSdoOk, false);
  return Step::kDone;
}

bool GatewayNetwork::run(ProgressHook* progress) {
  progress_ = progress;
  while (pending_ > 0) {
    // The next node with something queued after the one served last: every
    // node gets its turn, as the SocketCAN clients all run at once.
    uint8_t id = last_node_;
    for (int k = 0; k < 128; ++k) {
      id = static_cast<uint8_t>((id + 1) & 0x7F);
      if (!queues_[id].empty()) break;
    }
    if (queues_[id].empty()) break;  // pending_ counts no queued transfer: never
    last_node_ = id;
    Transfer* t = queues_[id].front();
    if (t->not_before_us != 0) {
      // A poll's pause: the gateway serves one request at a time anyway.
      const uint32_t now = now_us();
      if (!time_reached(now, t->not_before_us)) {
        const uint32_t wait_us = t->not_before_us - now;
        timespec pause = {static_cast<time_t>(wait_us / 1000000u),
                          static_cast<long>(wait_us % 1000000u) * 1000L};
        nanosleep(&pause, nullptr);  // pacing, not synchronisation
      }
    }
    queues_[id].pop_front();
    running_ = t;
    moved_ = size_ = 0;
    t->started = true;
    t->started_us = now_us();
    const Step s = t->upload ? upload(t) : download(t);
    running_ = nullptr;
    if (s == Step::kInterrupted && !t->finished) {
      // Interrupted on the line: this one ends with the rest (the caller aborts).
      queues_[id].push_front(t);
      progress_ = nullptr;
      return false;
    }
  }
  progress_ = nullptr;
  return true;
}

}  // namespace master
}  // namespace mb2co
