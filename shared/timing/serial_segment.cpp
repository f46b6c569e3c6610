#include "timing/serial_segment.h"

#include "timing/can_bits.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing {
namespace {

using serialnet::Access;
using serialnet::BusConfig;

bool token_mode(const BusConfig& c) {
  return c.access == Access::kToken || c.access == Access::kTokenStarter;
}

uint32_t byte_us(const BusConfig& c) {
  return serialnet::byte_time_us(c.baud);
}

uint32_t sum_windows_us(const BusConfig& c) {
  uint32_t sum = 0;
  for (uint16_t n = c.first_node; n <= c.last_node; ++n)
    sum += serialnet::window_of(c, static_cast<uint8_t>(n));
  return sum;
}

uint8_t nodes(const BusConfig& c) {
  return c.last_node >= c.first_node ? static_cast<uint8_t>(1u + c.last_node - c.first_node) : uint8_t{0};
}

}  // namespace

SerialMessageTime serial_message_time(const serialnet::ConnectionSet& set, uint32_t baud,
                                      uint8_t data_bytes) {
  if (data_bytes > serialnet::kMaxDataBytes) data_bytes = serialnet::kMaxDataBytes;
  // Content after the flag: id, length, data, CRC; each byte may be stuffed.
  const uint8_t content = static_cast<uint8_t>(serialnet::id_bytes(set) + 1u + data_bytes + 2u);
  SerialMessageTime t;
  t.bytes = static_cast<uint8_t>(1u + content);
  t.bytes_worst = static_cast<uint8_t>(1u + 2u * content);
  const uint32_t per_byte = serialnet::byte_time_us(baud);
  t.us = t.bytes * per_byte;
  t.worst_us = t.bytes_worst * per_byte;
  return t;
}

uint32_t serial_sync_us(const BusConfig& c) {
  return serialnet::max_sync_bytes(c.set) * byte_us(c);
}

uint32_t poll_cycle_us(const BusConfig& c) {
  return sum_windows_us(c) + nodes(c) * serial_sync_us(c);
}

uint32_t token_round_us(const BusConfig& c, uint8_t missing) {
  return sum_windows_us(c) + missing * token_recovery_us(c);
}

uint32_t token_round_idle_us(const BusConfig& c) {
  return nodes(c) * serial_sync_us(c);
}

uint32_t token_recovery_us(const BusConfig& c) {
  // The same terms as SerialLink::token_recovery_bound_us (one W_max: longest_window).
  return serialnet::longest_window(c) + c.guard_us + serial_sync_us(c);
}

uint32_t access_cycle_us(const BusConfig& c, uint8_t missing) {
  return token_mode(c) ? token_round_us(c, missing) : poll_cycle_us(c);
}

SerialLatency serial_latency(const BusConfig& c, uint8_t node, uint8_t data_bytes,
                             const uint8_t* ahead_data_bytes, uint8_t ahead_count, uint8_t missing) {
  SerialLatency l = {};
  l.wait_us = access_cycle_us(c, missing);
  for (uint8_t i = 0; i < ahead_count; ++i) {
    l.ahead_us += serial_message_time(c.set, c.baud, ahead_data_bytes[i]).worst_us;
  }
  l.own_us = serial_message_time(c.set, c.baud, data_bytes).worst_us;
  const uint32_t reserved = c.guard_us + (token_mode(c) ? serial_sync_us(c) : 0u);
  const uint32_t w = serialnet::window_of(c, node);
  l.budget_us = w > reserved ? w - reserved : 0u;
  l.fits = l.ahead_us + l.own_us <= l.budget_us;
  l.worst_us = l.fits ? l.wait_us + l.ahead_us + l.own_us : 0u;
  return l;
}

uint32_t serial_to_can_us(const SerialLatency& serial, uint32_t forward_us, uint32_t can_bitrate_bps,
                          uint8_t dlc) {
  const uint64_t frame_ns = bits_to_ns_ceil(frame_bits_worst(false, dlc, WorstCase::kDavis), can_bitrate_bps);
  return serial.worst_us + forward_us + static_cast<uint32_t>((frame_ns + 999u) / 1000u);
}

SerialLatency can_to_serial(const BusConfig& c, uint8_t bridge_node, uint8_t data_bytes,
                            const uint8_t* ahead_data_bytes, uint8_t ahead_count, uint32_t forward_us) {
  SerialLatency l = serial_latency(c, bridge_node, data_bytes, ahead_data_bytes, ahead_count, 0);
  if (l.fits) l.worst_us += forward_us;
  return l;
}

}  // namespace timing
}  // namespace mb2co
