// Test helpers for the SDO client suites: one CAN bus in virtual time that
// carries frames between our SdoClients and SdoServers in send order (so
// several transfers interleave frame by frame), with a hook that may drop or
// change a frame on the way; and a RAM domain object (sdo_domain.h) with a
// staging area, for objects far larger than the OD holds.
#pragma once
#include <stdint.h>
#include <string.h>

#include <deque>
#include <functional>
#include <vector>

#include "canopen/can_frame.h"
#include "canopen/sdo_client.h"
#include "canopen/sdo_domain.h"
#include "canopen/sdo_server.h"
#include "frame_log.h"

namespace mb2co {
namespace test {

/// A DOMAIN object at (index, sub) held in a vector; downloads go to a
/// staging vector and replace the content at commit() only.
class RamDomain {
 public:
  RamDomain(uint16_t index, uint8_t sub, uint32_t max_size) : index_(index), sub_(sub), max_(max_size) {}

  std::vector<uint8_t> content;
  int commits = 0;
  int begins = 0;

  canopen::SdoDomain table() {
    return canopen::SdoDomain{&RamDomain::owns,
                              &RamDomain::size,
                              &RamDomain::read,
                              &RamDomain::begin,
                              &RamDomain::write,
                              &RamDomain::commit,
                              this};
  }

 private:
  static RamDomain& self(void* ctx) { return *static_cast<RamDomain*>(ctx); }
  static bool owns(void* ctx, uint16_t index, uint8_t sub) {
    return index == self(ctx).index_ && sub == self(ctx).sub_;
  }
  static uint32_t size(void* ctx, uint16_t, uint8_t) {
    return static_cast<uint32_t>(self(ctx).content.size());
  }
  static canopen::SdoAbort read(void* ctx, uint16_t, uint8_t, uint32_t offset, uint8_t* buf, uint16_t n) {
    const RamDomain& d = self(ctx);
    if (offset + n > d.content.size()) return canopen::kAbortGeneral;
    memcpy(buf, d.content.data() + offset, n);
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort begin(void* ctx, uint16_t, uint8_t, uint32_t size, bool indicated) {
    RamDomain& d = self(ctx);
    if (indicated && size > d.max_) return canopen::kAbortTooLong;
    d.staging_.clear();
    ++d.begins;
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort write(void* ctx, uint16_t, uint8_t, uint32_t offset, const uint8_t* data,
                                 uint16_t n) {
    RamDomain& d = self(ctx);
    if (offset != d.staging_.size()) return canopen::kAbortGeneral;  // must come in order
    if (offset + n > d.max_) return canopen::kAbortTooLong;
    d.staging_.insert(d.staging_.end(), data, data + n);
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort commit(void* ctx, uint16_t, uint8_t, uint32_t size) {
    RamDomain& d = self(ctx);
    if (size != d.staging_.size()) return canopen::kAbortGeneral;
    d.content.swap(d.staging_);
    d.staging_.clear();
    ++d.commits;
    return canopen::kSdoOk;
  }

  uint16_t index_;
  uint8_t sub_;
  uint32_t max_;
  std::vector<uint8_t> staging_;
};

/// One CAN bus: every frame sent goes into one FIFO and is handed, in
/// order, to the server whose request id it carries and to every client.
class SdoBus {
 public:
  struct Server {
    canopen::SdoServer* server;
    uint8_t node_id;
  };
  std::vector<Server> servers;
  std::vector<canopen::SdoClient*> clients;
  uint32_t now = 0;  ///< virtual µs clock
  /// Sees every frame before delivery; may change it; false drops it.
  std::function<bool(CanFrame&)> tamper;
  /// Every frame delivered (after tamper), in bus order.
  std::vector<CanFrame> log;

  CanSink sink() { return CanSink{&SdoBus::send, this}; }

  /// Delivers the next queued frame; false when none is queued.
  bool step() {
    if (queue_.empty()) return false;
    CanFrame f = queue_.front();
    queue_.pop_front();
    if (tamper && !tamper(f)) return true;
    log.push_back(f);
    for (Server& s : servers) {
      if (f.id == 0x600u + s.node_id) s.server->on_frame(f, now, sink());
    }
    for (canopen::SdoClient* c : clients) c->on_frame(f, now, sink());
    return true;
  }

  bool any_client_busy() const {
    for (const canopen::SdoClient* c : clients) {
      if (c->busy()) return true;
    }
    return false;
  }

  /// Runs until every client is done: frames first; when the bus is quiet,
  /// virtual time jumps to the earliest deadline and everyone's process()
  /// runs. Gives up after `limit_us` of virtual time.
  void run(uint32_t limit_us = 60000000u) {
    const uint32_t start = now;
    while (any_client_busy() || !queue_.empty()) {
      if (step()) continue;
      NextDeadline d(now);
      for (Server& s : servers) s.server->next_deadline(d);
      for (canopen::SdoClient* c : clients) c->next_deadline(d);
      uint32_t at = 0;
      if (!d.result(&at)) return;
      now = at;
      if (now - start > limit_us) return;
      for (Server& s : servers) s.server->process(now, sink());
      for (canopen::SdoClient* c : clients) c->process(now, sink());
    }
  }

  /// Frames queued but not yet delivered.
  size_t queued() const { return queue_.size(); }

 private:
  static bool send(void* ctx, const CanFrame& f) {
    static_cast<SdoBus*>(ctx)->queue_.push_back(f);
    return true;
  }
  std::deque<CanFrame> queue_;
};

/// Bytes of a pattern that shows a shifted or repeated segment: byte i =
/// (i * 7 + seed) mod 251 (251 is prime: no period of 7 or 256).
inline std::vector<uint8_t> pattern(uint32_t n, uint32_t seed = 1) {
  std::vector<uint8_t> v(n);
  for (uint32_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>((i * 7u + seed) % 251u);
  return v;
}

/// An SdoData over a vector that grows as an upload arrives (no limit of
/// its own) and serves a download from the same vector.
struct VectorData {
  std::vector<uint8_t> bytes;
  canopen::SdoData data() { return canopen::SdoData{&VectorData::write, &VectorData::read, this}; }
  static canopen::SdoAbort write(void* ctx, uint32_t offset, const uint8_t* d, uint16_t n) {
    VectorData& v = *static_cast<VectorData*>(ctx);
    if (offset != v.bytes.size()) return canopen::kAbortGeneral;  // in order, contiguous
    v.bytes.insert(v.bytes.end(), d, d + n);
    return canopen::kSdoOk;
  }
  static canopen::SdoAbort read(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n) {
    const VectorData& v = *static_cast<VectorData*>(ctx);
    if (offset + n > v.bytes.size()) return canopen::kAbortGeneral;
    memcpy(buf, v.bytes.data() + offset, n);
    return canopen::kSdoOk;
  }
};

}  // namespace test
}  // namespace mb2co
