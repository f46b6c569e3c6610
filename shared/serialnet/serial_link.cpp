#include "serialnet/serial_link.h"

#include <string.h>

namespace mb2co {
namespace serialnet {
namespace {

inline void bump(uint16_t& counter) {
  if (counter != 0xFFFFu) ++counter;
}

const uint16_t kCanSync = 0x080;  // 3-bit code 1, node id 0: the same in every set

}  // namespace

uint32_t window_of(const BusConfig& c, uint8_t node) {
  if (c.node_windows_us == nullptr || node < c.first_node || node > c.last_node) return c.window_us;
  return c.node_windows_us[node - c.first_node];
}

uint32_t longest_window(const BusConfig& c) {
  uint32_t longest = c.window_us;
  if (c.node_windows_us == nullptr) return longest;
  longest = 0;
  for (uint16_t n = c.first_node; n <= c.last_node; ++n) {
    const uint32_t w = window_of(c, static_cast<uint8_t>(n));
    if (w > longest) longest = w;
  }
  return longest;
}

ConfigError check_config(const BusConfig& c) {
  if (c.baud == 0) return ConfigError::kBaud;
  if (c.first_node == 0 || c.first_node > c.last_node || c.last_node > c.set.max_nodes) {
    return ConfigError::kNodeRange;
  }
  const uint32_t byte_us = byte_time_us(c.baud);
  const bool token = c.access == Access::kToken || c.access == Access::kTokenStarter;
  const uint32_t needed_us =
      c.guard_us + (token ? max_sync_bytes(c.set) * byte_us : 0u) + kMaxEncodedBytes * byte_us;
  for (uint16_t n = c.first_node; n <= c.last_node; ++n) {
    if (window_of(c, static_cast<uint8_t>(n)) < needed_us) return ConfigError::kWindowTooShort;
  }
  return ConfigError::kOk;
}

SerialLink::SerialLink(const BusConfig& config, uint8_t node_id, const modbus::ByteSink& line)
    : config_(config),
      line_(line),
      decoder_(config.set, config.max_gap_us),
      byte_us_(byte_time_us(config.baud)),
      longest_window_us_(longest_window(config)),
      node_id_(node_id) {}

uint8_t SerialLink::next_node(uint8_t id) const {
  if (id < config_.first_node || id >= config_.last_node) return config_.first_node;
  return static_cast<uint8_t>(id + 1u);
}

uint8_t SerialLink::sync_frame_bytes() const {
  return max_sync_bytes(config_.set);
}

uint32_t SerialLink::token_recovery_bound_us() const {
  return longest_window_us_ + config_.guard_us + line_time_us(sync_frame_bytes());
}

bool SerialLink::to_message(const CanFrame& f, SerialMessage* m) const {
  if (f.rtr() || f.extended() || f.id > 0x7FFu) return false;
  if (can_to_serial(config_.set, static_cast<uint16_t>(f.id), &m->id) != MapResult::kOk) return false;
  m->length = f.dlc > kMaxDataBytes ? kMaxDataBytes : f.dlc;
  memcpy(m->data, f.data, m->length);
  // Seed 003 §3.2.2: unused SDO bytes are left off. CiA 301 sends them as
  // zeros, so the trailing zeros are what the receiver pads back: lossless
  // without parsing the SDO protocol.
  if (is_default_sdo(static_cast<uint16_t>(f.id))) {
    while (m->length > 0 && m->data[m->length - 1u] == 0) --m->length;
  }
  return true;
}

bool SerialLink::send(const CanFrame& f) {
  SerialMessage m;
  if (!to_message(f, &m)) {
    bump(counters_.unmappable_tx);
    return true;
  }
  // Seed 003 §3.2.5: a PDO due (changed, or its timer expired) goes out in
  // the next window, with the data it has by then; a second one due while
  // the first waits replaces it instead of queueing stale values.
  const bool queued = is_pdo(static_cast<uint16_t>(f.id)) ? queue_.replace_or_push(f) : queue_.push(f);
  if (!queued) {
    bump(counters_.overflow);
    return false;
  }
  return true;
}

void SerialLink::on_byte(uint8_t byte, uint32_t byte_us) {
  if (decoder_.push(byte, byte_us) != Decoder::kMessage) return;
  deliver(decoder_.message(), decoder_.message_us());
}

void SerialLink::deliver(const SerialMessage& m, uint32_t at_us) {
  settle(at_us);  // what we sent before this message came first
  uint16_t can_id = 0;
  if (serial_to_can(config_.set, m.id, &can_id) != MapResult::kOk) {
    bump(counters_.unmappable_rx);
    return;
  }
  last_activity_us_ = at_us;
  CanFrame f = {};
  f.id = can_id;
  f.dlc = m.length;
  memcpy(f.data, m.data, m.length);
  if (is_default_sdo(can_id)) f.dlc = 8;  // the left-off bytes were zeros
  // A poller owns the schedule: a SYNC it did not send opens nothing.
  if (can_id == kCanSync && m.length == 1 && config_.access != Access::kPoller)
    begin_window(m.data[0], at_us);
  bump(counters_.received);
  if (receiver_.receive != nullptr) receiver_.receive(receiver_.ctx, f, at_us);
}

void SerialLink::begin_window(uint8_t owner, uint32_t at_us) {
  owner_ = owner;
  window_start_us_ = at_us;
  mine_ = node_id_ != 0 && owner == node_id_;
  if (mine_) bump(counters_.windows);
}

uint32_t SerialLink::data_limit_us() const {
  uint32_t limit = window_start_us_ + window_of(config_, owner_) - config_.guard_us;
  if (token_mode()) limit -= line_time_us(sync_frame_bytes());
  return limit;
}

bool SerialLink::head_fits(uint32_t now_us, uint8_t* bytes, uint8_t* n) const {
  if (queue_.empty()) return false;
  SerialMessage m;
  if (!to_message(queue_.front(), &m)) return false;  // checked by send(): cannot happen
  *n = encode(config_.set, m, bytes, kMaxEncodedBytes);
  return *n != 0 && time_reached(data_limit_us(), now_us + line_time_us(*n));
}

bool SerialLink::write(const uint8_t* bytes, uint8_t n, uint32_t now_us) {
  if (!line_.write(line_.ctx, bytes, n)) {
    bump(counters_.line_refused);
    return false;
  }
  busy_ = true;
  busy_until_us_ = now_us + line_time_us(n);
  last_activity_us_ = busy_until_us_;
  bump(counters_.sent);
  return true;
}

bool SerialLink::transmit_head(uint32_t now_us) {
  uint8_t bytes[kMaxEncodedBytes];
  uint8_t n = 0;
  if (!head_fits(now_us, bytes, &n) || !write(bytes, n, now_us)) return false;
  queue_.pop_front();
  return true;
}

void SerialLink::send_sync(uint8_t counter, uint32_t now_us) {
  SerialMessage m;
  if (can_to_serial(config_.set, kCanSync, &m.id) != MapResult::kOk) return;  // every set has SYNC
  m.length = 1;
  m.data[0] = counter;
  uint8_t bytes[kMaxEncodedBytes];
  const uint8_t n = encode(config_.set, m, bytes, kMaxEncodedBytes);
  if (n == 0 || !write(bytes, n, now_us)) return;
  mine_ = false;  // a token is passed by this; a poll window ends with it
  started_ = true;
  sync_pending_ = true;
  sync_counter_ = counter;
}

void SerialLink::settle(uint32_t now_us) {
  if (!busy_ || !time_reached(now_us, busy_until_us_)) return;
  busy_ = false;
  if (!sync_pending_) return;
  // Our SYNC has left: the named node's window began at its end, and our
  // own node sees the SYNC like every other (SYNC consumers, sync PDOs).
  sync_pending_ = false;
  begin_window(sync_counter_, busy_until_us_);
  CanFrame f = {};
  f.id = kCanSync;
  f.dlc = 1;
  f.data[0] = sync_counter_;
  if (receiver_.receive != nullptr) receiver_.receive(receiver_.ctx, f, busy_until_us_);
}

void SerialLink::process(uint32_t now_us) {
  settle(now_us);
  if (busy_) return;
  const uint32_t window_end_us = window_start_us_ + window_of(config_, owner_);
  switch (config_.access) {
    case Access::kPolled:
      if (mine_ && time_reached(now_us, window_end_us)) mine_ = false;
      if (mine_) transmit_head(now_us);
      return;
    case Access::kPoller:
      if (!started_ || time_reached(now_us, window_end_us)) {
        send_sync(started_ ? next_node(owner_) : config_.first_node, now_us);
      } else if (mine_) {
        transmit_head(now_us);
      }
      return;
    case Access::kToken:
    case Access::kTokenStarter:
      if (mine_) {
        if (!transmit_head(now_us)) send_sync(next_node(node_id_), now_us);
      } else if (config_.access == Access::kTokenStarter) {
        if (!started_) {
          send_sync(config_.first_node, now_us);
        } else if (time_reached(now_us, last_activity_us_ + longest_window_us_ + config_.guard_us)) {
          // Nothing for W + G since our last message or the last one received
          // intact: the named node is missing, died in its window, or noise
          // spoiled a pass. The next one gets the token.
          bump(counters_.token_recoveries);
          send_sync(next_node(owner_), now_us);
        }
      }
      return;
  }
}

void SerialLink::next_deadline(NextDeadline& d) const {
  if (busy_) return d.at(busy_until_us_);
  const uint32_t now_us = d.now_us();
  const uint32_t window_end_us = window_start_us_ + window_of(config_, owner_);
  uint8_t bytes[kMaxEncodedBytes];
  uint8_t n = 0;
  switch (config_.access) {
    case Access::kPolled:
      if (!mine_) return;
      if (head_fits(now_us, bytes, &n)) return d.now();
      return d.at(window_end_us);  // closes the window
    case Access::kPoller:
      if (!started_) return d.now();
      if (mine_ && head_fits(now_us, bytes, &n)) return d.now();
      return d.at(window_end_us);
    case Access::kToken:
    case Access::kTokenStarter:
      if (mine_) return d.now();  // talk or pass
      if (config_.access != Access::kTokenStarter) return;
      if (!started_) return d.now();
      return d.at(last_activity_us_ + longest_window_us_ + config_.guard_us);
  }
}

}  // namespace serialnet
}  // namespace mb2co
