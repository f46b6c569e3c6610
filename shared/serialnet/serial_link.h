// The adapter that runs the unchanged node core (canopen::Node, SdoClient,
// anything that talks through a CanSink) on a serial multi-drop line, and the
// bus access of seed 003 §3.2.5-3.2.7 that decides when this device talks.
//
// Frames the core sends (can_sink()) are mapped to the connection set and
// queued in CAN priority order (TxQueue; a PDO replaces a waiting one of the
// same id: only the newest process data is sent); they go out only in this
// node's window, highest priority first, and only when they end inside it:
// what does not fit waits for the next window. Bytes from the line (on_byte) are
// decoded, mapped back to CAN ids (default-SDO messages padded to 8 bytes)
// and handed to the receiver (Node::receive) with the stamp of their last
// byte. A window is opened by a SYNC carrying one counter byte, the id of the
// node whose window it is (CAN 080h, 3-bit code 1 with node id 0).
//
// Access methods (BusConfig::access):
//  * Polling (one SYNC producer): the kPoller device sends SYNC(n) for
//    n = first_node..last_node in turn, each W_n after the last (window_us,
//    or node n's own length from node_windows_us); node n (kPolled) may talk
//    from the end of that SYNC until W_n - guard_us (G) later. The poller's
//    own node id, if in the range, gets its window like the others.
//    Cycle time = sum over the nodes of (W_n + the SYNC's line time).
//  * Token passing (multiple SYNC producers): the node named by a SYNC holds
//    the token; it sends what it has (what fits before W - T_sync) and then
//    SYNC(next), next = id + 1, after last_node back to first_node: at once
//    when its queue is empty, at the latest when its window ends. The
//    kTokenStarter sends the first SYNC and watches the line: when nothing
//    valid was received for W_max + G (the longest W: a holder it did not
//    hear named may have it) after the last message it received or sent,
//    the token is lost (the named node is missing, or died mid-window); it then sends
//    SYNC(next of the last named node). Recovery bound, from the end of the
//    last message the starter received intact or sent itself (noise may
//    have spoiled its own pass) to the end of the starter's new SYNC:
//        T_recover = W_max + G + T_sync,  T_sync = sync_frame_bytes() * t_byte,
//    t_byte = 10 bits / baud. A missing node costs that once per cycle (the
//    ring is first..last; nodes do not learn who is absent). A missing
//    starter is not recovered: it must be on the segment.
//    T_sync is reserved at the end of every token window for the pass, so a
//    holder's last SYNC ends at or before window start + W: a token round
//    takes at most the sum of the W_n, plus T_recover per missing node.
//
// What the nodes' ODs need: 1019h (SYNC counter overflow) not 0, so that a
// SYNC with its counter byte is a SYNC to them and not a length error (EMCY
// 8240h); the number of nodes is the natural value. A synchronous TPDO
// (types 1..240) counts every poll SYNC. Heartbeat consumer times (1016h)
// must allow for a window's wait: a cycle more than the producer's 1017h.
//
// Contract: call process() after the node core's process() in the same pass
// (so what the core queued at this instant counts as pending), and at the
// time next_deadline() gives. The port must not hand the device its own
// bytes back (an RS-485 echo): the link knows what it sent. One context; no
// heap; 245 bytes of RAM on the AVR (112 of them the queue).
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/clock.h"
#include "platform/device_port.h"  // CanSink, modbus::ByteSink: the ports' contract
#include "serialnet/connection_set.h"
#include "serialnet/frame_codec.h"
#include "serialnet/tx_queue.h"

namespace mb2co {
namespace serialnet {

/// Who may talk when (seed 003 §3.2.5).
enum class Access : uint8_t {
  kPolled,        ///< a node of a polled segment: talks in the window its SYNC opens
  kPoller,        ///< the single SYNC producer (it may have a node id and window too)
  kToken,         ///< a node of a token-passing segment
  kTokenStarter,  ///< kToken that also starts the token and recovers it when lost
};

/// The segment's settings: the same on every device of it (access and the
/// node's own id excepted).
struct BusConfig {
  ConnectionSet set;
  uint32_t baud;  ///< line bit rate (8-N-1: 10 bits per byte)
  Access access;
  uint8_t first_node;  ///< node ids polled / in the token ring: first..last
  uint8_t last_node;   ///< <= set.max_nodes
  uint32_t window_us;  ///< W: one window per node per cycle, from the end of its SYNC
  /// Optional: node n's own W at [n - first_node] (last - first + 1 entries,
  /// caller-owned, constant, outliving the links); null: window_us for all.
  const uint32_t* node_windows_us;
  uint32_t guard_us;    ///< G: silence kept before the window ends (turnaround, clock offsets)
  uint32_t max_gap_us;  ///< Decoder: longest silence inside a message (0: no limit)
};

/// Why a BusConfig cannot work.
enum class ConfigError : uint8_t {
  kOk,
  kBaud,            ///< 0: no byte time
  kNodeRange,       ///< not 1 <= first_node <= last_node <= set.max_nodes
  kWindowTooShort,  ///< W - G (- T_sync when passing a token) holds no longest message
};
/// Checks `config` before a link uses it (a port's command line, a test).
ConfigError check_config(const BusConfig& config);
/// W of node `node` (its node_windows_us entry, else window_us; window_us
/// for ids outside first..last).
uint32_t window_of(const BusConfig& config, uint8_t node);
/// The longest W of the segment.
uint32_t longest_window(const BusConfig& config);

/// Bytes of a SYNC message in `set` with the longest stuffing (T_sync).
inline uint8_t max_sync_bytes(const ConnectionSet& set) {
  // Flag, then id, length, counter and CRC, each possibly stuffed.
  return static_cast<uint8_t>(1u + 2u * (id_bytes(set) + 1u + 1u + 2u));
}

/// Where decoded frames go: Node::receive (serial_node.h) or a bridge.
struct CanReceiver {
  void (*receive)(void* ctx, const CanFrame& f, uint32_t now_us);
  void* ctx;
};

class SerialLink {
 public:
  /// `node_id` names this device's window (0: none, e.g. a pure poller).
  /// `line` gets one whole message per write (platform/device_port.h rules).
  SerialLink(const BusConfig& config, uint8_t node_id, const modbus::ByteSink& line);

  void set_receiver(const CanReceiver& receiver) { receiver_ = receiver; }
  /// The CanSink for the node core: its send() queues (see send()).
  CanSink can_sink() { return CanSink{&SerialLink::sink_send, this}; }

  /// A frame to transmit in our window. A PDO replaces a waiting one with
  /// the same id (its newest data leaves in the window). False when the
  /// queue is full (the sender retries; each refusal counts as overflow).
  /// A frame that has no serial form (extended, remote, unmappable id) is
  /// dropped, counted, and reported as sent (true): retrying cannot help.
  bool send(const CanFrame& f);
  /// A byte from the line, `byte_us` when it was complete.
  void on_byte(uint8_t byte, uint32_t byte_us);
  /// Bus access: ends our transmissions, sends what our window allows, the
  /// poller's and the token's SYNCs, the starter's recovery.
  void process(uint32_t now_us);
  /// Lowers `d` to when process() must run next (now: we may talk now).
  void next_deadline(NextDeadline& d) const;

  /// Bytes of the SYNC message with the longest stuffing (T_sync above).
  uint8_t sync_frame_bytes() const;
  /// Line time of `bytes` bytes (µs).
  uint32_t line_time_us(uint8_t bytes) const { return bytes * byte_us_; }
  /// T_recover of the header comment (µs).
  uint32_t token_recovery_bound_us() const;

  /// The node whose window is current (last SYNC seen or sent; 0: none yet).
  uint8_t window_owner() const { return owner_; }
  bool holds_token() const { return mine_ && token_mode(); }
  /// True while this node's window is open (polling) or it holds the token.
  bool in_window() const { return mine_; }
  uint8_t node_id() const { return node_id_; }
  const BusConfig& config() const { return config_; }
  uint8_t queued() const { return queue_.size(); }

  /// Counters that never decrement (saturate at 0xFFFF).
  struct Counters {
    uint16_t sent;              ///< messages written to the line (SYNCs included)
    uint16_t received;          ///< messages handed to the receiver
    uint16_t overflow;          ///< send() calls refused: queue full
    uint16_t unmappable_tx;     ///< frames with no serial form, dropped
    uint16_t unmappable_rx;     ///< messages with a reserved or foreign id, dropped
    uint16_t line_refused;      ///< the port's write refused a message (retried)
    uint16_t windows;           ///< windows (or tokens) we got
    uint16_t token_recoveries;  ///< starter: lost tokens recovered
  };
  const Counters& counters() const { return counters_; }
  const Decoder::Counters& decoder_counters() const { return decoder_.counters(); }

 private:
  static bool sink_send(void* ctx, const CanFrame& f) { return static_cast<SerialLink*>(ctx)->send(f); }
  bool token_mode() const {
    return config_.access == Access::kToken || config_.access == Access::kTokenStarter;
  }
  uint8_t next_node(uint8_t id) const;
  /// Ends our message on the line if it ended by `now_us`; a SYNC of ours
  /// then opens the window it names (even when process() ran late).
  void settle(uint32_t now_us);
  /// A window begins at `at_us` (the end of SYNC(owner)).
  void begin_window(uint8_t owner, uint32_t at_us);
  /// Our last moment for data (window end less G, less T_sync in token mode).
  uint32_t data_limit_us() const;
  /// Encodes the queue's front if it ends by data_limit_us(); false if not.
  bool head_fits(uint32_t now_us, uint8_t* bytes, uint8_t* n) const;
  bool transmit_head(uint32_t now_us);
  void send_sync(uint8_t counter, uint32_t now_us);
  bool write(const uint8_t* bytes, uint8_t n, uint32_t now_us);
  /// Serial form of `f` (SDO trailing zeros left off); false: none.
  bool to_message(const CanFrame& f, SerialMessage* m) const;
  void deliver(const SerialMessage& m, uint32_t at_us);

  BusConfig config_;
  modbus::ByteSink line_;
  CanReceiver receiver_ = {nullptr, nullptr};
  Decoder decoder_;
  TxQueue queue_;
  Counters counters_ = {};
  uint32_t byte_us_;
  uint32_t longest_window_us_;  ///< W_max, from the config at construction
  uint32_t busy_until_us_ = 0;  ///< end of our message on the line (valid while busy_)
  uint32_t window_start_us_ = 0;
  uint32_t last_activity_us_ = 0;  ///< end of the last valid message seen or sent
  uint8_t node_id_;
  uint8_t owner_ = 0;
  uint8_t sync_counter_ = 0;  ///< the SYNC on the line now (valid while sync_pending_)
  bool busy_ = false;
  bool sync_pending_ = false;  ///< our message on the line is a SYNC: its end opens a window
  bool started_ = false;       ///< poller / starter: the first SYNC went out
  bool mine_ = false;          ///< our window is open / we hold the token
};

}  // namespace serialnet
}  // namespace mb2co
