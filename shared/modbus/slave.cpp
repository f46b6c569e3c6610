// Slave: framing outcome → counters → addressing → listen-only/broadcast
// rules → execute → answer. The function codes are in slave_data.cpp and
// slave_diagnostics.cpp.
#include "modbus/slave.h"

#include "crc/crc16.h"
#include "modbus/network_pdu.h"

namespace mb2co {
namespace modbus {
namespace {

bool valid_address(uint8_t address) {
  return address != kBroadcastAddress && address <= kMaxServerAddress;
}

// Only these are executed when broadcast (serial line spec §2.1: broadcast
// requests are writes). FC 17 returns data, so it is not among them; of
// FC 2Bh/0Dh only its NMT command is a write (docs/gateway-network.md).
bool broadcast_allowed(const uint8_t* pdu, uint16_t pdu_length) {
  const uint8_t function = pdu[0];
  if (profile::kNetwork && is_net_nmt_pdu(pdu, pdu_length)) return true;
  return function == fc::kWriteSingleCoil || function == fc::kWriteSingleRegister ||
         function == fc::kWriteMultipleCoils || function == fc::kWriteMultipleRegisters;
}

}  // namespace

SlaveCore::SlaveCore(RegisterBank& bank, DeviceIdentity* identity, ByteSink sink, uint8_t address,
                     const RtuTiming& timing, uint8_t* frame, uint16_t frame_bytes)
    : SlaveCoreState(),
      bank_(bank),
      identity_(identity),
      sink_(sink),
      framer_(timing, frame, frame_bytes),
      address_(valid_address(address) ? address : 1u) {}

bool SlaveCore::set_address(uint8_t address) {
  if (!valid_address(address)) return false;
  address_ = address;
  return true;
}

void SlaveCore::on_char(uint8_t byte, uint32_t byte_us, bool error) {
  if (framer_.frame_due_before(byte_us)) handle_frame();
  if (profile::kNetwork && line_answer_pending()) {  // the master sent something else: it gave the answer up
    answer_pending_ = false;
    ++counters_.no_responses;
  }
  framer_.push_char(byte, byte_us, error);
}

void SlaveCore::process(uint32_t now_us) {
  if (framer_.frame_due(now_us)) handle_frame();
  framer_.tick(now_us);
}

void SlaveCore::clear_counters() {
  counters_ = DiagCounters{};
}

void SlaveCore::handle_frame() {
  switch (framer_.finish()) {
    case FrameStatus::kOk:
      break;
    case FrameStatus::kOverrun:
      ++counters_.char_overruns;
      return;
    case FrameStatus::kT15Violation:
      ++stats_.t15_violations;
      ++counters_.bus_comm_errors;
      return;
    case FrameStatus::kBadCrc:
    case FrameStatus::kTooShort:
    case FrameStatus::kCharError:
      ++counters_.bus_comm_errors;
      return;
  }
  ++counters_.bus_messages;
  const uint8_t target = framer_.buffer()[0];
  const bool broadcast = target == kBroadcastAddress;
  if (!broadcast && target != address_) return;  // another slave's frame
  ++counters_.server_messages;
#if MB2CO_CONFIG_MODBUS_TCP
  channel_ = nullptr;  // the request in hand is the line's
#endif
  handle_request(static_cast<uint16_t>(framer_.length() - 1u - kCrcBytes), broadcast);
#if MB2CO_CONFIG_MODBUS_TCP
  channel_ = answer_pending_ ? answer_channel_ : nullptr;
#endif
}

void SlaveCore::handle_request(uint16_t pdu_length, bool broadcast) {
  if (line_listen_only()) {
    // Serial line spec: in listen-only mode only 08/01 is acted upon, and it
    // is not answered. It clears the counters, so nothing is counted for it.
    if (!broadcast && is_restart_request(pdu_length)) {
      listen_only_ = false;
      clear_counters();
    } else {
      ++counters_.no_responses;
    }
    return;
  }
  const uint8_t function = pdu()[0];
  if (broadcast && !broadcast_allowed(pdu(), pdu_length)) {
    ++counters_.no_responses;
    return;
  }
  const Reply reply = execute(pdu_length);
  if (reply.exception != Exception::kNone) {
    ++counters_.exceptions;  // broadcast ones too (CPT3)
    if (broadcast) {
      ++counters_.no_responses;
    } else {
      pdu()[0] = static_cast<uint8_t>(function | fc::kExceptionFlag);
      pdu()[1] = static_cast<uint8_t>(reply.exception);
      send(2);
    }
  } else if (profile::kNetwork && deferred_in_hand()) {
    // 2B/0D deferred: counted when it is sent or dropped.
  } else if (broadcast || reply.pdu_length == 0u) {
    ++counters_.no_responses;  // broadcast, or 08/04 (never answered)
  } else {
    if (profile::kNetwork && (pdu()[0] & fc::kExceptionFlag) != 0u) {
      ++counters_.exceptions;  // 2B/0D: 04 with an abort code
    }
    send(reply.pdu_length);
  }
  if (restart_pending_) {  // 08/01: answered first, then restarted
    restart_pending_ = false;
    listen_only_ = false;
    clear_counters();
  }
}

bool SlaveCore::send_deferred(uint16_t pdu_length) {
  if (!answer_pending_) return false;
  answer_pending_ = false;
  if ((pdu()[0] & fc::kExceptionFlag) != 0u) ++counters_.exceptions;
  send(pdu_length);
#if MB2CO_CONFIG_MODBUS_TCP
  channel_ = answer_channel_ = nullptr;
#endif
  return true;
}

void SlaveCore::send(uint16_t pdu_length) {
#if MB2CO_CONFIG_MODBUS_TCP
  if (channel_ != nullptr) return send_to_channel(pdu_length);
#endif
  uint8_t* adu = framer_.buffer();
  adu[0] = address_;
  const uint16_t length = append_crc(adu, static_cast<uint16_t>(pdu_length + 1u));
  if (sink_.write == nullptr || !sink_.write(sink_.ctx, adu, length)) {
    ++stats_.send_failures;
    ++counters_.no_responses;
  }
}

SlaveCore::Reply SlaveCore::execute(uint16_t pdu_length) {
  switch (pdu()[0]) {
    case fc::kReadCoils:
      return read(pdu_length, Table::kCoils);
    case fc::kReadDiscreteInputs:
      return read(pdu_length, Table::kDiscreteInputs);
    case fc::kReadHoldingRegisters:
      return read(pdu_length, Table::kHoldingRegisters);
    case fc::kReadInputRegisters:
      return read(pdu_length, Table::kInputRegisters);
    case fc::kWriteSingleCoil:
      return write_single_coil(pdu_length);
    case fc::kWriteSingleRegister:
      return write_single_register(pdu_length);
    case fc::kDiagnostics:
      // An image whose profile leaves FC 08 out answers it as any code it
      // does not know.
      if (!profile::kDiagnostics) return Reply{0, Exception::kIllegalFunction};
      return diagnostics(pdu_length);
    case fc::kWriteMultipleCoils:
      return write_multiple(pdu_length, Table::kCoils);
    case fc::kWriteMultipleRegisters:
      return write_multiple(pdu_length, Table::kHoldingRegisters);
    case fc::kReadWriteMultipleRegisters:
      return read_write_registers(pdu_length);
    case fc::kEncapsulatedInterface:
      return device_identification(pdu_length);
    default:
      return Reply{0, Exception::kIllegalFunction};
  }
}

}  // namespace modbus
}  // namespace mb2co
