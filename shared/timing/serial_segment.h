// Timing of CANopen on a serial multi-drop segment (seed 003 §3.2.5-3.2.7,
// shared/serialnet): message times at the baud rate, the polling cycle, the
// token round, the token's recovery time and the worst-case latency of one
// message under either access method, plus what a smart bridge adds.
//
// The segment is described by the serialnet::BusConfig its links run on, so
// the bound and the schedule cannot disagree about windows or guard time.
// Times are whole µs. A byte takes serialnet::byte_time_us(baud): 10 bits at
// the baud rate rounded up to whole µs (87 µs at 115200), exactly the byte
// time the links plan their windows with; a real UART's byte is never longer,
// so every bound below holds on the line as well as in the simulator.
//
// The model (serial_link.h has the schedule these follow):
//  * message bytes: flag, id (1 byte; 2 in the 11-bit set), length, data, CRC 2
//    (1 + id + 1 + n + 2); in the worst case every byte after the flag is
//    stuffed (1 + 2 (id + 1 + n + 2)): 25 for 8 data bytes, 27 with a 2-byte id.
//  * T_sync: a SYNC (1 counter byte) with the worst stuffing.
//  * polling: the poller names node n in turn, W_n after the previous SYNC
//    ended: cycle = sum over the nodes of (W_n + T_sync).
//  * token passing: a holder passes by the end of its window (it keeps
//    T_sync for the pass): round <= sum of W_n, plus T_recover per missing
//    node; an idle round (everyone passes at once) ~ N T_sync.
//    T_recover = W_max + G + T_sync.
//  * latency of a message from the moment its node queues it to the end of
//    its last byte: it may just have missed its node's window, so it waits
//    up to one cycle (one token round) for the next window start, then the
//    messages of higher priority queued with it go first (the queue sends
//    the lowest CAN id first), then itself:
//        L <= cycle (round) + ahead + own,  ahead + own <= W_n - G (- T_sync).
//    This is the data-link author's "cycle + W" made exact for the message.
//    When the message and what is ahead do not fit one window the bound is
//    refused (fits = false): the queue could starve it.
//  * bridge: a frame forwarded onto the segment waits like any message of
//    the bridge's own node (one window wait plus the frame time); a message
//    forwarded to CAN adds the bridge's forwarding time and the CAN frame.
#pragma once
#include <stdint.h>

#include "serialnet/serial_link.h"

namespace mb2co {
namespace timing {

/// Bytes and line time of one message with `data_bytes` (0..8) data bytes.
struct SerialMessageTime {
  uint8_t bytes;        ///< nothing stuffed (nominal)
  uint8_t bytes_worst;  ///< every byte after the flag stuffed
  uint32_t us;          ///< bytes at the link's byte time
  uint32_t worst_us;    ///< bytes_worst at the link's byte time
};
/// `data_bytes` above 8 counts as 8 (the codec carries no more).
SerialMessageTime serial_message_time(const serialnet::ConnectionSet& set, uint32_t baud, uint8_t data_bytes);

/// T_sync: the SYNC with its counter byte, worst stuffing (µs).
uint32_t serial_sync_us(const serialnet::BusConfig& c);
/// Polling: sum over first..last of (W_n + T_sync) (µs).
uint32_t poll_cycle_us(const serialnet::BusConfig& c);
/// Token passing: sum over first..last of W_n, plus T_recover for each of
/// `missing` nodes of the ring that are not on the segment (µs).
uint32_t token_round_us(const serialnet::BusConfig& c, uint8_t missing);
/// Token passing with nothing to send: every holder passes at once (µs).
uint32_t token_round_idle_us(const serialnet::BusConfig& c);
/// T_recover = W_max + G + T_sync (µs): from the end of the last message the
/// starter received intact or sent to the end of its recovering SYNC.
uint32_t token_recovery_us(const serialnet::BusConfig& c);
/// The cycle of c.access: poll_cycle_us (kPolled, kPoller) or
/// token_round_us(c, missing) (kToken, kTokenStarter).
uint32_t access_cycle_us(const serialnet::BusConfig& c, uint8_t missing);

/// Worst-case latency of one message of node `node` (µs), see above.
struct SerialLatency {
  bool fits;           ///< ahead + own fit node's window: the bound holds
  uint32_t wait_us;    ///< for the node's next window: a cycle or a token round
  uint32_t ahead_us;   ///< the higher-priority messages sent first (worst stuffing)
  uint32_t own_us;     ///< the message itself (worst stuffing)
  uint32_t budget_us;  ///< W_n - G (polling), W_n - G - T_sync (token)
  uint32_t worst_us;   ///< wait + ahead + own (0 when !fits)
};
/// `ahead_data_bytes[0, ahead_count)`: the data lengths of the messages of
/// higher priority the node may have queued with it (at most one per id:
/// the queue keeps the newest PDO only). `missing`: ring nodes absent (token
/// passing only; ignored when polling).
SerialLatency serial_latency(const serialnet::BusConfig& c, uint8_t node, uint8_t data_bytes,
                             const uint8_t* ahead_data_bytes, uint8_t ahead_count, uint8_t missing);

/// A message from a serial node through a bridge onto CAN: its serial
/// latency, `forward_us` in the bridge (receive to CAN transmit request) and
/// the CAN frame with worst-case stuffing (Davis) at `can_bitrate_bps`, µs
/// rounded up. Queueing behind other CAN traffic is the CAN analysis' part
/// (rta.h) and not included.
uint32_t serial_to_can_us(const SerialLatency& serial, uint32_t forward_us, uint32_t can_bitrate_bps,
                          uint8_t dlc);
/// A CAN frame forwarded onto the segment by the bridge (node
/// `bridge_node` of `c`): `forward_us`, then one window wait plus the frame
/// time, as any message of the bridge's node. worst_us includes forward_us.
SerialLatency can_to_serial(const serialnet::BusConfig& c, uint8_t bridge_node, uint8_t data_bytes,
                            const uint8_t* ahead_data_bytes, uint8_t ahead_count, uint32_t forward_us);

}  // namespace timing
}  // namespace mb2co
