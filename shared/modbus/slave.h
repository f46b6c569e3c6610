// Modbus/RTU slave (server): byte-fed, time handed in, data behind a
// RegisterBank. Function codes 01 02 03 04 05 06 0F 10 17, 08 (diagnostics),
// 2B/0E (device identification, basic category, conformity level 0x81).
//
// Usage (main loop, one context):
//   slave.begin(now);                        // optional: power-up wait of t3.5
//   for each received byte:  slave.on_byte(b, stamp_us);
//   regularly:               slave.process(now_us);
// Call process() with a `now_us` taken before the port was last found empty,
// so that no byte that arrived before `now_us` is still unread.
// Responses go out through the ByteSink from inside process() (or on_byte(),
// when process() was late and a new frame starts after t3.5).
// On the host a second framer may hand in requests: serve() takes a PDU
// from Modbus/TCP (modbus/tcp_framer.h) and answers it through its
// PduChannel, the same function codes behind both (profile::kModbusTcp).
//
// Rules. Broadcast (address 0): only 05 06 0F 10 are executed (and, where
// FC 2Bh/0Dh is built in, its NMT command), nothing is ever answered; other
// broadcast requests are ignored (counted unanswered).
// Listen-only mode (08/04): frames are counted, only 08/01 to our address is
// acted upon (it ends the mode, clears the counters and is not answered).
// Exceptions, checked in this order (application protocol state diagrams):
// 01 function or sub-function not supported; 03 malformed request (quantity,
// byte count, length, FC 05 value, FC 08 data field, 2B read code); 02 an
// address outside what RegisterBank::covers(); 04 (or the bank's code) when
// executing fails.
//
// Memory: the frame buffer (request, then response in place) and ~50 bytes
// of state. Slave owns a 256-byte buffer: every request the protocol allows.
// SlaveCore takes a smaller caller-owned one (the Uno's gateway: its register
// maps are short). Then a longer request is lost like one beyond 256 bytes
// (counted in CPT8 08/12, not answered), and a covered read whose response
// would not fit is answered with exception 04; device identification objects
// are cut to the room there is.
#pragma once
#include <stdint.h>

#include "modbus/byte_sink.h"
#include "modbus/net_switch.h"
#include "modbus/protocol.h"
#include "modbus/register_bank.h"
#include "modbus/rtu_framer.h"
#include "modbus/rtu_timing.h"
#include "profiles/profile.h"
#if MB2CO_CONFIG_MODBUS_TCP
#include "modbus/tcp_channel.h"
#endif

namespace mb2co {
namespace modbus {

/// The FC 2Bh / MEI 0Dh service behind a slave (gateway/network_service.h).
/// `handle` gets the request PDU in the frame buffer (function code first,
/// `pdu_length` bytes) and builds the response in place, at most
/// `capacity` bytes. It returns the response PDU length to send now (an
/// exception PDU has the exception flag in its first byte), or 0 when the
/// answer comes later through SlaveCore::send_deferred(). Called from
/// process()/on_char(); it must not call them.
struct NetRequestHandler {
  uint16_t (*handle)(void* ctx, uint8_t* pdu, uint16_t pdu_length, uint16_t capacity);
  void* ctx;
};

/// Smallest frame buffer a slave takes: an empty FC 2B/0E response (12 bytes)
/// and every fixed-size response (write echoes, FC 08: 8 bytes) fit.
constexpr uint16_t kMinSlaveFrameBytes = 16;

/// Diagnostic counters, serial line spec V1.02 §6.1 (16 bits, wrap around).
/// Cleared by power-up, 08/01 restart and 08/0A; 08/14 clears only overruns.
struct DiagCounters {
  uint16_t bus_messages;     ///< CPT1 08/0B: frames with a good CRC, any address
  uint16_t bus_comm_errors;  ///< CPT2 08/0C: bad CRC, < 4 bytes, t1.5 gap, parity
  uint16_t exceptions;       ///< CPT3 08/0D: exceptions, including broadcast ones
  uint16_t server_messages;  ///< CPT4 08/0E: good frames for us or broadcast
  uint16_t no_responses;     ///< CPT5 08/0F: of those, not answered
  uint16_t char_overruns;    ///< CPT8 08/12: frames longer than the buffer, 256
                             ///< bytes or less (any address: the rest is lost)
};

/// Counters outside the Modbus model (never cleared, for logs and tests).
struct LinkStats {
  uint16_t t15_violations;  ///< frames discarded for a gap > t1.5 (also in CPT2)
  uint16_t send_failures;   ///< responses the ByteSink refused (also in CPT5)
};

/// The state of a SlaveCore that starts at zero: one block, value-initialised
/// by the SlaveCore's constructor (one zero-fill instead of a store per
/// member, as NodeState).
struct SlaveCoreState {
  DiagCounters counters_;
  LinkStats stats_;
  bool listen_only_;
  bool restart_pending_;  ///< 08/01 answered: restart after sending
  // FC 2Bh/0Dh (profile::kNetwork; never set in a profile without it).
  const NetRequestHandler* net_handler_;  ///< FC 2Bh/0Dh service; null: exception 01
  bool answer_pending_;                   ///< a 2B/0D answer is deferred (see answer_pending())
#if MB2CO_CONFIG_MODBUS_TCP               // the service's own state: no RAM where the profile leaves it out
  PduChannel* channel_;                   ///< where the request in hand came from (null: the RTU framer)
  PduChannel* answer_channel_;            ///< where the deferred answer goes (null: the RTU line)
#endif
};

/// The slave on a caller-owned frame buffer (see Memory above).
class SlaveCore : private SlaveCoreState {
 public:
  /// `identity` may be null: FC 2B then answers exception 01.
  /// `address` outside 1..247 is replaced by 1 (check with set_address).
  /// `frame` holds `frame_bytes` bytes (kMinSlaveFrameBytes or more; at most
  /// kMaxAduBytes are used) and must outlive the slave.
  SlaveCore(RegisterBank& bank, DeviceIdentity* identity, ByteSink sink, uint8_t address,
            const RtuTiming& timing, uint8_t* frame, uint16_t frame_bytes);

  /// False (and no change) for an address outside 1..247.
  bool set_address(uint8_t address);
  uint8_t address() const { return address_; }
  void set_timing(const RtuTiming& timing) { framer_.set_timing(timing); }
  void set_check_t15(bool check) { framer_.set_check_t15(check); }

  void begin(uint32_t now_us) { framer_.begin(now_us); }
  /// A received character, stamped when it was complete (see rtu_framer.h).
  void on_byte(uint8_t byte, uint32_t byte_us) { on_char(byte, byte_us, false); }
  /// A character received with a parity or framing error.
  void on_char_error(uint32_t byte_us) { on_char(0, byte_us, true); }
  /// on_byte(), or on_char_error() when `error`: one path for both (the
  /// Uno's main loop hands in either).
  void on_char(uint8_t byte, uint32_t byte_us, bool error);
  /// Ends a frame after t3.5 of silence and answers it.
  void process(uint32_t now_us);
  /// When process() must run next at the latest; false: only after a byte.
  bool deadline(uint32_t& at_us) const { return framer_.deadline(at_us); }
  /// The same in the form of Node::next_deadline: false when nothing is
  /// pending (only a character makes work); else *at_us, the end of the
  /// frame in progress (t3.5 after its last character) or of the power-up
  /// wait. Invariant: process() called at *at_us, or after any later
  /// on_char(), does everything due; called earlier it changes nothing
  /// observable. `now_us` only states when the question is asked (a past
  /// deadline is returned as it is: time_reached() says it is due).
  bool next_deadline(uint32_t now_us, uint32_t* at_us) const {
    (void)now_us;
    return framer_.deadline(*at_us);
  }

  const DiagCounters& counters() const { return counters_; }
  const LinkStats& stats() const { return stats_; }
  bool listen_only() const { return listen_only_; }

 private:
  /// Outcome of executing one request PDU (buf_[1..]).
  struct Reply {
    uint16_t pdu_length;  ///< normal response PDU length (valid if exception == kNone)
    Exception exception;
  };

  void handle_frame();
  void handle_request(uint16_t pdu_length, bool broadcast);
  /// Listen-only mode (08/04) holds for the request in hand: it is the
  /// serial line's, a request from another framer is served anyway.
  bool line_listen_only() const {
#if MB2CO_CONFIG_MODBUS_TCP
    return listen_only_ && channel_ == nullptr;
#else
    return listen_only_;
#endif
  }
  void send(uint16_t pdu_length);
  void clear_counters();

  Reply execute(uint16_t pdu_length);
  Reply read(uint16_t pdu_length, Table table);            // FC 01 02 03 04
  Reply write_single_coil(uint16_t pdu_length);            // FC 05
  Reply write_single_register(uint16_t pdu_length);        // FC 06
  Reply write_multiple(uint16_t pdu_length, Table table);  // FC 0F 10
  Reply write_checked(Table table, uint16_t start, uint16_t quantity, const uint8_t* values);
  Reply read_write_registers(uint16_t pdu_length);
  Reply diagnostics(uint16_t pdu_length);
  Reply device_identification(uint16_t pdu_length);
  /// 08/01 request valid and we are in listen-only mode: restart, no answer.
  bool is_restart_request(uint16_t pdu_length) const;

  /// The PDU of the request in hand (or of the deferred answer).
  uint8_t* pdu() {
#if MB2CO_CONFIG_MODBUS_TCP
    if (channel_ != nullptr) return channel_->pdu;
#endif
    return framer_.buffer() + 1;
  }
  /// True when a response PDU of `pdu_length` bytes fits the frame buffer.
  bool fits(uint16_t pdu_length) const {
    return 1u + pdu_length + kCrcBytes <= framer_.capacity();
  }

  RegisterBank& bank_;
  DeviceIdentity* identity_;
  ByteSink sink_;
  RtuFramer framer_;
  uint8_t address_;

  // FC 2Bh / MEI 0Dh (profile::kNetwork): the service and its deferred
  // answer. In every profile; unused code is dropped where the switch is off.
 public:
  /// The FC 2Bh/0Dh service; null (the default): exception 01. Borrowed:
  /// it must outlive the slave or be cleared.
  void set_net_handler(const NetRequestHandler* handler) {
    net_handler_ = handler;
  }
  /// True while a deferred answer may still be sent: the handler deferred
  /// it and no character has been received since (the master gave it up
  /// once it sends anything else: a later answer could be taken for the
  /// answer to its next request).
  bool answer_pending() const {
    return answer_pending_;
  }
  /// The frame buffer's PDU area: where a deferred response is built. Only
  /// while answer_pending() (else a request may be arriving there).
  uint8_t* response_pdu() {
    return pdu();
  }
  uint16_t response_capacity() const {
    return static_cast<uint16_t>(framer_.capacity() - 1u - kCrcBytes);
  }
  /// Sends the deferred response of `pdu_length` bytes built in
  /// response_pdu(). False, nothing sent, when no answer is pending.
  bool send_deferred(uint16_t pdu_length);

 private:
  Reply network_request(uint16_t pdu_length);
  /// True when the deferred answer is the serial line's: a character from
  /// the line drops it, not one a Modbus/TCP client is waiting for.
  bool line_answer_pending() const {
#if MB2CO_CONFIG_MODBUS_TCP
    return answer_pending_ && answer_channel_ == nullptr;
#else
    return answer_pending_;
#endif
  }
  /// True when the request in hand deferred its answer (at most one answer
  /// is deferred at a time: the service answers 06 to another while its
  /// transfer runs).
  bool deferred_in_hand() const {
#if MB2CO_CONFIG_MODBUS_TCP
    return answer_pending_ && answer_channel_ == channel_;
#else
    return answer_pending_;
#endif
  }

#if MB2CO_CONFIG_MODBUS_TCP
  // Modbus/TCP (profile::kModbusTcp): requests from another framer.
 public:
  /// Serves the request PDU of `pdu_length` bytes (1..kMaxPduBytes) in
  /// `channel.pdu`, whatever the unit id it came with (a Modbus/TCP server
  /// is addressed by its IP address), and answers through channel.send: at
  /// once, or when done for an FC 2Bh/0Dh the service defers (the channel
  /// must then stay until the answer or forget()). A request on a channel
  /// whose answer is still deferred drops that answer (its client moved
  /// on, as a master on the line does). FC 08 is the serial line's
  /// (application protocol §6.8): exception 01; listen-only mode is the
  /// line's and does not apply. Counted in CPT1 and CPT4 like a frame from
  /// the line: the line application's watchdog (2000h/9) sees it.
  void serve(PduChannel& channel, uint16_t pdu_length);
  /// The channel goes away (its connection closed): an answer deferred for
  /// it is dropped (counted in CPT5) and the channel is no longer used.
  void forget(const PduChannel& channel);

 private:
  /// A response PDU to the channel in hand (no address, no CRC).
  void send_to_channel(uint16_t pdu_length);
#endif
};

/// Storage that must exist before SlaveCore is built from it (a base class).
/// Left uninitialised: the framer writes a byte before it reads it (length()
/// counts what was written), and a static slave's buffer is zero anyway.
template <uint16_t kFrameBytes>
struct SlaveFrame {
  uint8_t frame_[kFrameBytes];
};

/// A SlaveCore with its own frame buffer of kFrameBytes.
template <uint16_t kFrameBytes>
class SlaveWithFrame : private SlaveFrame<kFrameBytes>, public SlaveCore {
 public:
  static_assert(kFrameBytes >= kMinSlaveFrameBytes && kFrameBytes <= kMaxAduBytes, "RTU frame size");
  SlaveWithFrame(RegisterBank& bank, DeviceIdentity* identity, ByteSink sink, uint8_t address,
                 const RtuTiming& timing)
      : SlaveCore(bank, identity, sink, address, timing, this->frame_, kFrameBytes) {}
};

/// The slave with a buffer for every request the protocol allows.
using Slave = SlaveWithFrame<kMaxAduBytes>;

}  // namespace modbus
}  // namespace mb2co
